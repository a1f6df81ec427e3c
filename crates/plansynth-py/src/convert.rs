//! Cell and behaviour sets between Python and the core: little-endian bytes in Python,
//! 64-bit words in the core.
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// The first `nw` words of a little-endian byte string (missing bytes are zero).
pub fn words(mask: &[u8], nw: usize) -> Vec<u64> {
    let mut out = vec![0u64; nw];
    for (i, b) in mask.iter().enumerate() {
        if i / 8 < nw {
            out[i / 8] |= (*b as u64) << (8 * (i % 8));
        }
    }
    out
}

/// [`words`] of a Python bytes object.
pub fn bits_of(b: &Bound<'_, PyBytes>, nw: usize) -> Vec<u64> {
    words(b.as_bytes(), nw)
}

/// Words as a little-endian Python bytes object.
pub fn bytes_of<'py>(py: Python<'py>, m: &[u64]) -> Bound<'py, PyBytes> {
    let v: Vec<u8> = m.iter().flat_map(|w| w.to_le_bytes()).collect();
    PyBytes::new(py, &v)
}

//! Sets of grid cells as 64-bit words, and the few word operations the game needs.

/// A set of cells: bit `i` of word `i / 64` is cell `i` (`y * width + x`).
pub type Bits = Vec<u64>;

/// Move every cell of `src` by `d` cells (no border check: callers mask first).
#[inline]
pub fn shift(src: &[u64], d: i64, out: &mut [u64]) {
    let nw = src.len();
    out.iter_mut().for_each(|w| *w = 0);
    let (ws, bs) = (
        d.unsigned_abs() as usize / 64,
        (d.unsigned_abs() % 64) as u32,
    );
    if ws >= nw {
        return;
    }
    if d >= 0 {
        for i in (ws..nw).rev() {
            let lo = src[i - ws];
            let mut v = lo << bs;
            if bs > 0 && i > ws {
                v |= src[i - ws - 1] >> (64 - bs);
            }
            out[i] = v;
        }
    } else {
        for i in 0..nw - ws {
            let mut v = src[i + ws] >> bs;
            if bs > 0 && i + ws + 1 < nw {
                v |= src[i + ws + 1] << (64 - bs);
            }
            out[i] = v;
        }
    }
}

#[inline]
pub fn bit(m: &[u64], i: usize) -> bool {
    m[i / 64] >> (i % 64) & 1 == 1
}

/// Indices of the set bits, ascending.
#[inline]
pub fn ones_of(m: &[u64]) -> Vec<usize> {
    let mut out = vec![];
    for (i, &w) in m.iter().enumerate() {
        let mut w = w;
        while w != 0 {
            let b = w.trailing_zeros() as usize;
            out.push(i * 64 + b);
            w &= w - 1;
        }
    }
    out
}

#[inline]
pub fn any(m: &[u64]) -> bool {
    m.iter().any(|&w| w != 0)
}

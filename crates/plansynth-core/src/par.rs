//! Threads for the hot loops: the environment variable `PLANSYNTH_THREADS` says how
//! many (default 1: the loops run on the calling thread, as before). Work is split
//! into contiguous ranges, one per thread, with `std::thread::scope`, and the results
//! come back in range order, so every answer is the one a single thread gives.

use std::ops::Range;

/// The threads the hot loops may use (`PLANSYNTH_THREADS`, at least 1; default 1).
pub fn threads() -> usize {
    std::env::var("PLANSYNTH_THREADS")
        .ok()
        .and_then(|v| v.trim().parse::<usize>().ok())
        .unwrap_or(1)
        .clamp(1, 256)
}

/// `f` over `0..n` split into at most [`threads`] contiguous ranges (none shorter than
/// `min_len`, except the last), the results in order.
pub fn map_ranges<T, F>(n: usize, min_len: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(Range<usize>) -> T + Sync,
{
    let t = threads().min(n.div_ceil(min_len.max(1))).max(1);
    if t == 1 {
        return vec![f(0..n)];
    }
    let step = n.div_ceil(t);
    let ranges: Vec<Range<usize>> = (0..t)
        .map(|i| (i * step).min(n)..((i + 1) * step).min(n))
        .collect();
    std::thread::scope(|s| {
        let handles: Vec<_> = ranges
            .into_iter()
            .map(|r| {
                let f = &f;
                s.spawn(move || f(r))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a worker thread panicked"))
            .collect()
    })
}

/// `f` on each part, one thread a part (in parallel up to [`threads`]: the callers
/// make at most that many parts).
pub fn run_parts<T, F>(parts: Vec<T>, f: F)
where
    T: Send,
    F: Fn(T) + Sync,
{
    if parts.len() <= 1 {
        parts.into_iter().for_each(f);
        return;
    }
    std::thread::scope(|s| {
        for p in parts {
            let f = &f;
            s.spawn(move || f(p));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_cover_in_order() {
        let parts = map_ranges(10, 1, |r| r.collect::<Vec<_>>());
        let all: Vec<usize> = parts.into_iter().flatten().collect();
        assert_eq!(all, (0..10).collect::<Vec<_>>());
    }
}

//! The held-out steps: gains are measured only on steps no fit saw.
//!
//! The split is interleaved and deterministic: along every path, every third
//! step (the 3rd, 6th, 9th, … of the path) is held out and the others train.
//! Whole paths still run in order (the state a held-out step starts from is
//! the one its path reached), so the split leaves the load history alone; it
//! only decides which residuals a fit minimises and which ones judge it. A
//! path with fewer than three steps is all training.

/// Which steps a residual or an RMS is taken over.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subset {
    Training,
    HeldOut,
    All,
}

/// Whether step `k` (0-based) of a path is held out.
pub fn held_out(k: usize) -> bool {
    k % 3 == 2
}

impl Subset {
    pub fn contains(self, _path: usize, k: usize) -> bool {
        match self {
            Subset::Training => !held_out(k),
            Subset::HeldOut => held_out(k),
            Subset::All => true,
        }
    }
}

/// The number of steps of a path of `n` steps in `subset`.
pub fn count(subset: Subset, n: usize) -> usize {
    (0..n).filter(|&k| subset.contains(0, k)).count()
}

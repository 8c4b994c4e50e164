//! Arrays over the padded cells whose starts are spread over the memory page.
//!
//! The step's loops read and write a dozen arrays at the same index in the same pass
//! (the stage values, the RK4 sums, the start state, the accelerations). An array of more
//! than 128 kB comes from the allocator as fresh pages, so all of them would start at the
//! same offset in a 4096-byte page; a load from one array and a store to another at the
//! same index then have the same low 12 address bits, and the CPU, which compares only
//! those bits to see whether a load depends on an earlier store, stalls the load
//! ("4K aliasing"). Measured (docs/benchmarks.md, "The lattice against a bare stencil"):
//! the RK4 step over 134 x 134 sliding blocks ran at 1.2e8 block-steps per CPU second with
//! its arrays so placed, 2.0e8 with them spread. A [`CellVec`] starts at its own offset
//! in the page (array k of the process at 576 k mod 4096 bytes: 64 offsets, 64 bytes
//! apart), at the cost of one page of padding per array; arrays of less than 128 kB are
//! left where the allocator puts them. Where an array lies changes no result.

use std::sync::atomic::{AtomicUsize, Ordering};

/// The page whose offsets are spread over (bytes).
const PAGE: usize = 4096;
/// The step between the offsets of consecutive arrays (bytes; 9 cache lines: the 64
/// multiples of 64 bytes below `PAGE` in turn).
const STRIDE: usize = 9 * 64;

/// Arrays of this many values and more are spread (128 kB: the allocator's smallest
/// threshold for handing out fresh pages; smaller arrays follow one another in its heap,
/// at offsets that differ already).
const SPREAD_FROM: usize = 16 * 1024;

/// The number of spread arrays made so far (their offsets in turn).
static MADE: AtomicUsize = AtomicUsize::new(0);

/// A fixed-length array of f64 starting at its own offset in the memory page (module
/// docs); it reads and writes as a slice.
pub struct CellVec {
    /// The allocation (never resized after it is made: `at` points into it; it owns
    /// the values, which are read through `at`).
    #[allow(dead_code)]
    buf: Vec<f64>,
    /// The first value: `off` values into `buf` (a pointer, not an offset, so that
    /// reading the array costs what reading a `Vec` costs: no bounds check of the slice).
    at: std::ptr::NonNull<f64>,
    len: usize,
}

// SAFETY: a CellVec owns its values as a Vec<f64> does (`at` points into its own `buf`,
// which moves with it and is never reallocated), so it is sent and shared as a Vec is.
unsafe impl Send for CellVec {}
// SAFETY: as above; `&CellVec` gives only shared access to the values.
unsafe impl Sync for CellVec {}

impl CellVec {
    /// An array of `len` values `x` (of zeros: pages untouched until written).
    pub fn new(len: usize, x: f64) -> CellVec {
        if len == 0 {
            return CellVec::default();
        }
        if len < SPREAD_FROM {
            // a small array: where the allocator puts it (after the one before it)
            let mut buf = vec![x; len];
            let at = std::ptr::NonNull::from(&mut buf[..]).cast::<f64>();
            return CellVec { buf, at, len };
        }
        CellVec::in_turn(len, x, MADE.fetch_add(1, Ordering::Relaxed))
    }

    /// The array made k-th: it starts at offset k STRIDE (mod PAGE) in the page.
    fn in_turn(len: usize, x: f64, k: usize) -> CellVec {
        let lanes = PAGE / std::mem::size_of::<f64>();
        let mut buf = vec![x; len + lanes];
        let target = (k * STRIDE) % PAGE;
        let start = buf.as_ptr() as usize % PAGE;
        // (f64 is 8-byte aligned and target a multiple of 8: a whole number of values)
        let off = ((target + PAGE - start) % PAGE) / std::mem::size_of::<f64>();
        let at = std::ptr::NonNull::from(&mut buf[off..off + len]).cast::<f64>();
        CellVec { buf, at, len }
    }

    /// An array holding a copy of `x`.
    pub fn from_slice(x: &[f64]) -> CellVec {
        let mut a = CellVec::new(x.len(), 0.0);
        a.copy_from_slice(x);
        a
    }
}

impl Default for CellVec {
    /// The empty array.
    fn default() -> CellVec {
        CellVec {
            buf: Vec::new(),
            at: std::ptr::NonNull::dangling(),
            len: 0,
        }
    }
}

impl std::ops::Deref for CellVec {
    type Target = [f64];
    #[inline(always)]
    fn deref(&self) -> &[f64] {
        // SAFETY: `at` and `len` are a run of initialised values inside `buf` (or a
        // dangling pointer and 0), borrowed with `self`
        unsafe { std::slice::from_raw_parts(self.at.as_ptr(), self.len) }
    }
}

impl std::ops::DerefMut for CellVec {
    #[inline(always)]
    fn deref_mut(&mut self) -> &mut [f64] {
        // SAFETY: as in `deref`, borrowed mutably with `self`
        unsafe { std::slice::from_raw_parts_mut(self.at.as_ptr(), self.len) }
    }
}

impl Clone for CellVec {
    /// A copy at an offset of its own.
    fn clone(&self) -> CellVec {
        CellVec::from_slice(self)
    }
}

impl std::fmt::Debug for CellVec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl PartialEq for CellVec {
    fn eq(&self, other: &CellVec) -> bool {
        **self == **other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_start_at_spread_offsets_and_hold_their_values() {
        // 64 arrays made in turn start at the 64 distinct 64-byte offsets in the page
        // (large ones: fresh pages from the allocator, which would all start alike); values, clones and equality as a slice
        let n = 20_000;
        // (the k-th array made: tests in other threads make arrays too)
        let arrays: Vec<CellVec> = (0..64).map(|k| CellVec::in_turn(n, k as f64, k)).collect();
        let mut offsets: Vec<usize> = arrays.iter().map(|a| a.as_ptr() as usize % PAGE).collect();
        for (k, a) in arrays.iter().enumerate() {
            assert_eq!(a.len(), n);
            assert!(a.iter().all(|&x| x == k as f64));
            assert_eq!(offsets[k], (k * STRIDE) % PAGE);
        }
        assert!(offsets.iter().all(|o| o % 64 == 0), "{offsets:?}");
        offsets.sort_unstable();
        offsets.dedup();
        assert_eq!(offsets.len(), 64, "offsets not distinct");
        assert!(CellVec::new(n, 0.0).as_ptr() as usize % 64 == 0);
        assert_eq!(&CellVec::new(3, 2.0)[..], &[2.0; 3]);
        let mut b = arrays[3].clone();
        assert_eq!(b, arrays[3]);
        assert_ne!(b.as_ptr(), arrays[3].as_ptr());
        b[n - 1] = -1.0;
        assert_ne!(b, arrays[3]);
        assert_eq!(CellVec::default().len(), 0);
        assert_eq!(CellVec::new(0, 1.0).len(), 0);
        assert_eq!(&CellVec::from_slice(&[1.0, 2.0])[..], &[1.0, 2.0]);
    }
}

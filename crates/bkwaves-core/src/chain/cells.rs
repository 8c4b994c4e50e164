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

impl CellVec {
    /// Give the memory pages that lie wholly inside values [lo, hi) back to the system
    /// (Linux: `madvise(MADV_DONTNEED)`; elsewhere nothing is done): their values read
    /// back as 0.0 and take memory again once written. For values whose contents are
    /// dead (written before they are next read: ../release.rs). Returns the bytes given
    /// back (0 where nothing was).
    pub fn release(&mut self, lo: usize, hi: usize) -> usize {
        let hi = hi.min(self.len);
        if lo >= hi {
            return 0;
        }
        let page = sys::page();
        let base = self.at.as_ptr() as usize;
        let (start, end) = (
            (base + lo * 8).next_multiple_of(page),
            (base + hi * 8) / page * page,
        );
        if end <= start {
            return 0;
        }
        // SAFETY: [start, end) lies inside values [lo, hi) of this array, which `&mut
        // self` borrows alone; the pages stay mapped and read back as zeros, a valid f64.
        unsafe { sys::dont_need(start, end - start) }
    }

    /// The memory pages that hold values of this array: (resident, all) (Linux:
    /// `mincore`; None elsewhere or if the call fails). A page given back and read since
    /// counts as resident (it maps the system's shared page of zeros).
    pub fn resident_pages(&self) -> Option<(usize, usize)> {
        if self.len == 0 {
            return Some((0, 0));
        }
        let page = sys::page();
        let base = self.at.as_ptr() as usize;
        let (start, end) = (
            base / page * page,
            (base + self.len * 8).next_multiple_of(page),
        );
        // SAFETY: [start, end) are the pages holding this array's values, all mapped
        // (they belong to its allocation); mincore only reads the page tables.
        unsafe { sys::resident(start, end - start, page) }
    }
}

/// The resident bytes of the memory pages holding the `bytes` bytes at `ptr` of a live
/// allocation, as [`CellVec::resident_pages`] counts pages (measurements).
pub fn resident_bytes_of(ptr: *const u8, bytes: usize) -> Option<usize> {
    if bytes == 0 {
        return Some(0);
    }
    let page = sys::page();
    let base = ptr as usize;
    let (start, end) = (base / page * page, (base + bytes).next_multiple_of(page));
    // SAFETY: the caller's allocation holds [ptr, ptr + bytes), so the pages around it
    // are mapped; mincore only reads the page tables.
    unsafe { sys::resident(start, end - start, page) }.map(|(r, _)| r * page)
}

/// The system calls of [`CellVec::release`] and [`CellVec::resident_pages`].
#[cfg(target_os = "linux")]
mod sys {
    use std::sync::atomic::{AtomicUsize, Ordering};

    extern "C" {
        fn madvise(addr: *mut std::ffi::c_void, len: usize, advice: i32) -> i32;
        fn mincore(addr: *mut std::ffi::c_void, len: usize, vec: *mut u8) -> i32;
        fn sysconf(name: i32) -> i64;
    }
    const MADV_DONTNEED: i32 = 4;
    const SC_PAGESIZE: i32 = 30;
    static PAGE: AtomicUsize = AtomicUsize::new(0);

    /// The system's page size in bytes.
    pub fn page() -> usize {
        match PAGE.load(Ordering::Relaxed) {
            0 => {
                // SAFETY: sysconf reads a constant of the system
                let p = unsafe { sysconf(SC_PAGESIZE) };
                let p = if p > 0 { p as usize } else { 4096 };
                PAGE.store(p, Ordering::Relaxed);
                p
            }
            p => p,
        }
    }

    /// madvise(MADV_DONTNEED) over page-aligned [start, start + len): the bytes given back.
    ///
    /// # Safety
    /// The range must be mapped memory whose contents nobody needs (they become zeros).
    pub unsafe fn dont_need(start: usize, len: usize) -> usize {
        if madvise(start as *mut std::ffi::c_void, len, MADV_DONTNEED) == 0 {
            len
        } else {
            0
        }
    }

    /// mincore over page-aligned [start, start + len): (resident pages, pages).
    ///
    /// # Safety
    /// The range must be mapped memory.
    pub unsafe fn resident(start: usize, len: usize, page: usize) -> Option<(usize, usize)> {
        let n = len / page;
        let mut v = vec![0u8; n];
        if mincore(start as *mut std::ffi::c_void, len, v.as_mut_ptr()) != 0 {
            return None;
        }
        Some((v.iter().filter(|&&b| b & 1 == 1).count(), n))
    }
}

/// Elsewhere: nothing given back, residency unknown.
#[cfg(not(target_os = "linux"))]
mod sys {
    pub fn page() -> usize {
        4096
    }
    pub unsafe fn dont_need(_start: usize, _len: usize) -> usize {
        0
    }
    pub unsafe fn resident(_start: usize, _len: usize, _page: usize) -> Option<(usize, usize)> {
        None
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

    #[cfg(target_os = "linux")]
    #[test]
    fn released_pages_read_zero_and_leave_memory() {
        // the whole pages inside [lo, hi) read 0 and are no longer resident; every value
        // outside them is kept (the partial pages at the ends included)
        let n = 64 * 1024;
        let mut a = CellVec::new(n, 0.0);
        for (k, x) in a.iter_mut().enumerate() {
            *x = k as f64 + 1.0;
        }
        let (r0, all) = a.resident_pages().unwrap();
        assert_eq!(r0, all);
        let (lo, hi) = (1000, 50_000);
        let bytes = a.release(lo, hi);
        let page = sys::page();
        let base = a.as_ptr() as usize;
        let (start, end) = (
            (base + 8 * lo).next_multiple_of(page),
            (base + 8 * hi) / page * page,
        );
        assert_eq!(bytes, end - start);
        let (r1, _) = a.resident_pages().unwrap();
        assert_eq!(r0 - r1, bytes / page);
        // a page written again is resident again (one value: one page)
        a[2000] = 5.0;
        assert_eq!(a.resident_pages().unwrap().0, r1 + 1);
        a[2000] = 0.0;
        // (read after the counts: a page given back and read maps the zero page, which
        // mincore counts as resident)
        for (k, &x) in a.iter().enumerate() {
            let at = base + 8 * k;
            let gone = at >= start && at < end;
            assert_eq!(x, if gone { 0.0 } else { k as f64 + 1.0 }, "{k}");
        }
        assert_eq!(a.release(10, 20), 0);
        assert_eq!(a.release(hi, lo), 0);
    }
}

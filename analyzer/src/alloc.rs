//! A counting wrapper for the binary's global allocator: how many heap bytes
//! the process holds, so that the planner's memory limit is measured rather
//! than estimated.
//!
//! The binaries declare it (`#[global_allocator] static GLOBAL:
//! Counting<mimalloc::MiMalloc> = Counting::new(mimalloc::MiMalloc);`) and
//! pass [`in_use`] to the planner (`PlannerLimits::memory_in_use`). The cost
//! is one relaxed atomic addition per allocation and per deallocation.

use std::alloc::{GlobalAlloc, Layout};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Bytes allocated and not yet freed, through every [`Counting`] allocator
/// of the process (there is one global allocator).
static IN_USE: AtomicUsize = AtomicUsize::new(0);

/// The heap bytes the process holds, counted by [`Counting`]; 0 when the
/// process does not use it.
pub fn in_use() -> usize {
    IN_USE.load(Ordering::Relaxed)
}

/// A global allocator that counts the bytes it holds.
pub struct Counting<A>(A);

impl<A> Counting<A> {
    pub const fn new(inner: A) -> Self {
        Counting(inner)
    }
}

// SAFETY: every method forwards to the inner allocator with the same
// arguments and returns its result unchanged; the counter is bookkeeping.
unsafe impl<A: GlobalAlloc> GlobalAlloc for Counting<A> {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is the inner allocator's.
        let p = unsafe { self.0.alloc(layout) };
        if !p.is_null() {
            IN_USE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as for `alloc`.
        let p = unsafe { self.0.alloc_zeroed(layout) };
        if !p.is_null() {
            IN_USE.fetch_add(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by this allocator with `layout`.
        unsafe { self.0.dealloc(ptr, layout) };
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as for `dealloc`, and `new_size` is the caller's.
        let p = unsafe { self.0.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size >= layout.size() {
                IN_USE.fetch_add(new_size - layout.size(), Ordering::Relaxed);
            } else {
                IN_USE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::alloc::System;

    #[test]
    fn counts_what_is_held() {
        let a = Counting::new(System);
        let before = in_use();
        let layout = Layout::from_size_align(1 << 20, 8).unwrap();
        // SAFETY: a valid non-zero layout; the block is freed below with it.
        unsafe {
            let p = a.alloc(layout);
            assert!(!p.is_null());
            // Other tests of this process may allocate through the same
            // counter only if they use `Counting`, which none does.
            assert_eq!(in_use() - before, 1 << 20);
            let q = a.realloc(p, layout, 3 << 20);
            assert_eq!(in_use() - before, 3 << 20);
            a.dealloc(q, Layout::from_size_align(3 << 20, 8).unwrap());
        }
        assert_eq!(in_use(), before);
    }
}

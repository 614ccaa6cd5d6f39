//! A persistent vector: cloning shares everything, a write copies one chunk
//! of [`CHUNK`] elements and the spine (one pointer per chunk).
//!
//! Child plans are clones of their parent with a few changes: a step or a
//! link appended, a few earliest times raised. With 32-element chunks a child
//! of a 600-step plan copies a 19-pointer spine and one or two chunks instead
//! of 600 steps (docs/planner.md gives the measurements).

use std::rc::Rc;

pub const CHUNK: usize = 32;

#[derive(Clone)]
pub struct PVec<T: Clone> {
    chunks: Vec<Rc<Vec<T>>>,
    len: usize,
}

impl<T: Clone> Default for PVec<T> {
    fn default() -> Self {
        PVec { chunks: Vec::new(), len: 0 }
    }
}

impl<T: Clone + std::fmt::Debug> std::fmt::Debug for PVec<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Clone> PVec<T> {
    pub fn new() -> Self {
        PVec::default()
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    pub fn get(&self, i: usize) -> Option<&T> {
        if i >= self.len {
            return None;
        }
        self.chunks[i / CHUNK].get(i % CHUNK)
    }

    pub fn push(&mut self, value: T) {
        if self.len.is_multiple_of(CHUNK) {
            // Room for two: most plans are children that add a step (two
            // time points) and are never expanded; the chunk grows as
            // the plans that are expanded add more.
            let mut chunk = Vec::with_capacity(2);
            chunk.push(value);
            self.chunks.push(Rc::new(chunk));
        } else {
            let last = self.chunks.last_mut().expect("a partial chunk exists");
            match Rc::get_mut(last) {
                Some(own) => own.push(value),
                None => {
                    // A shared chunk is copied with room for this element
                    // and one more (a step adds two time points), not at
                    // its length, which the push would then double.
                    let mut copy = Vec::with_capacity((last.len() + 2).min(CHUNK));
                    copy.extend_from_slice(last);
                    copy.push(value);
                    *last = Rc::new(copy);
                }
            }
        }
        self.len += 1;
    }

    /// A mutable reference to element `i`, copying its chunk if it is shared.
    pub fn get_mut(&mut self, i: usize) -> Option<&mut T> {
        if i >= self.len {
            return None;
        }
        Rc::make_mut(&mut self.chunks[i / CHUNK]).get_mut(i % CHUNK)
    }

    pub fn set(&mut self, i: usize, value: T) {
        if let Some(slot) = self.get_mut(i) {
            *slot = value;
        }
    }

    pub fn iter(&self) -> impl Iterator<Item = &T> + '_ {
        self.chunks.iter().flat_map(|c| c.iter())
    }
}

impl<T: Clone> std::ops::Index<usize> for PVec<T> {
    type Output = T;
    fn index(&self, i: usize) -> &T {
        self.get(i).expect("index in bounds")
    }
}

impl<T: Clone> FromIterator<T> for PVec<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut v = PVec::new();
        for x in iter {
            v.push(x);
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_do_not_show_in_clones() {
        let mut a: PVec<u32> = (0..100).collect();
        let b = a.clone();
        a.set(40, 7);
        a.push(100);
        assert_eq!(a[40], 7);
        assert_eq!(b[40], 40);
        assert_eq!(b.len(), 100);
        assert_eq!(a.len(), 101);
        assert_eq!(a.iter().copied().filter(|&x| x == 7).count(), 2);
        assert!(a.get(101).is_none());
    }

    /// A child plan that pushes onto a chunk it shares with its parent
    /// copies the chunk with room for two more, not at its length (which
    /// the push would then double), and a new chunk starts small: most
    /// children are never expanded.
    #[test]
    fn a_shared_chunk_is_copied_at_its_new_length() {
        let parent: PVec<u64> = (0..17).collect();
        let mut child = parent.clone();
        child.push(17);
        let last = child.chunks.last().expect("a chunk");
        assert_eq!(last.len(), 18);
        assert!(last.capacity() <= 19, "capacity {}", last.capacity());
        assert_eq!(parent.len(), 17);
        let full: PVec<u64> = (0..CHUNK as u64).collect();
        let mut child = full.clone();
        child.push(0);
        assert!(child.chunks.last().expect("a chunk").capacity() <= 2);
    }
}

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

/// Elements per chunk of a [`PList`].
pub const LIST_CHUNK: usize = 8;

/// A persistent list for a plan's open links: cloning shares its chunks of
/// at most [`LIST_CHUNK`] elements; removing an element copies its chunk
/// (the others keep their place: the list keeps its order), appending
/// copies the last chunk if it is shared, and the spine is one pointer
/// per chunk (with the index of its first element: finding an element is
/// a binary search). A child plan removes the open link it solves and may append
/// a new step's: a copy of the whole list per child was about half of
/// what a child of a small plan owns (DriverLog: 52 open links of 36
/// bytes on average).
#[derive(Clone)]
pub struct PList<T: Clone> {
    /// Each chunk with the index of its first element.
    chunks: Vec<(usize, Rc<Vec<T>>)>,
    len: usize,
}

impl<T: Clone> Default for PList<T> {
    fn default() -> Self {
        PList { chunks: Vec::new(), len: 0 }
    }
}

impl<T: Clone + std::fmt::Debug> std::fmt::Debug for PList<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Clone> PList<T> {
    pub fn new() -> Self {
        PList::default()
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The chunk of element `i` and its place there.
    fn locate(&self, i: usize) -> Option<(usize, usize)> {
        if i >= self.len {
            return None;
        }
        let c = self.chunks.partition_point(|&(first, _)| first <= i).checked_sub(1)?;
        Some((c, i - self.chunks[c].0))
    }

    pub fn get(&self, i: usize) -> Option<&T> {
        self.locate(i).map(|(c, k)| &self.chunks[c].1[k])
    }

    pub fn iter(&self) -> impl Iterator<Item = &T> + '_ {
        self.chunks.iter().flat_map(|(_, c)| c.iter())
    }

    pub fn push(&mut self, value: T) {
        self.extend([value]);
    }

    /// Appends `items`: into the last chunk while it has room (copied once
    /// if shared, with room for what comes), then into new chunks.
    pub fn extend(&mut self, items: impl IntoIterator<Item = T>) {
        let mut items = items.into_iter().peekable();
        while items.peek().is_some() {
            let room = self.chunks.last().map_or(0, |(_, c)| LIST_CHUNK.saturating_sub(c.len()));
            if room == 0 {
                let chunk = Vec::with_capacity(LIST_CHUNK.min(items.size_hint().0.max(1)));
                self.chunks.push((self.len, Rc::new(chunk)));
                continue;
            }
            let (_, last) = self.chunks.last_mut().expect("a chunk with room");
            let own = match Rc::get_mut(last) {
                Some(own) => own,
                None => {
                    let mut copy =
                        Vec::with_capacity(LIST_CHUNK.min(last.len() + items.size_hint().0.max(1)));
                    copy.extend_from_slice(last);
                    *last = Rc::new(copy);
                    Rc::get_mut(last).expect("just made")
                }
            };
            for x in items.by_ref().take(room) {
                own.push(x);
                self.len += 1;
            }
        }
    }

    /// Removes element `i` (the elements after it move down by one).
    pub fn remove(&mut self, i: usize) -> T {
        let (c, k) = self.locate(i).expect("index in bounds");
        let chunk = &mut self.chunks[c].1;
        let removed = match Rc::get_mut(chunk) {
            Some(own) => own.remove(k),
            None => {
                let mut copy = Vec::with_capacity(chunk.len() - 1);
                copy.extend_from_slice(&chunk[..k]);
                copy.extend_from_slice(&chunk[k + 1..]);
                let removed = chunk[k].clone();
                *chunk = Rc::new(copy);
                removed
            }
        };
        for (first, _) in &mut self.chunks[c + 1..] {
            *first -= 1;
        }
        if self.chunks[c].1.is_empty() {
            self.chunks.remove(c);
        }
        self.len -= 1;
        removed
    }
}

impl<T: Clone> std::ops::Index<usize> for PList<T> {
    type Output = T;
    fn index(&self, i: usize) -> &T {
        self.get(i).expect("index in bounds")
    }
}

impl<T: Clone> FromIterator<T> for PList<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut v = PList::new();
        v.extend(iter);
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

    /// A list behaves as a vector (order kept through removals), and a
    /// clone that removes or appends copies one chunk, never the list.
    #[test]
    fn a_list_shares_all_but_the_chunks_it_writes() {
        let parent: PList<u32> = (0..50).collect();
        let mut model: Vec<u32> = (0..50).collect();
        let mut child = parent.clone();
        for i in [17, 0, 40, 7, 7, 7, 7, 7, 7, 7, 7, 30] {
            assert_eq!(child.remove(i), model.remove(i));
        }
        child.extend([100, 101, 102]);
        model.extend([100, 101, 102]);
        assert_eq!(child.iter().copied().collect::<Vec<_>>(), model);
        assert_eq!(child.len(), model.len());
        assert!((0..model.len()).all(|i| child[i] == model[i]));
        assert_eq!(parent.iter().copied().collect::<Vec<_>>(), (0..50).collect::<Vec<_>>());
        // One removal: every chunk but one still the parent's.
        let mut one = parent.clone();
        one.remove(20);
        let shared =
            one.chunks.iter().filter(|(_, c)| parent.chunks.iter().any(|(_, p)| Rc::ptr_eq(c, p))).count();
        assert_eq!(shared, one.chunks.len() - 1);
        // One append to a full last chunk: a new chunk of its own.
        let full: PList<u32> = (0..LIST_CHUNK as u32 * 2).collect();
        let mut more = full.clone();
        more.push(7);
        assert_eq!(more.chunks.len(), 3);
        assert!(Rc::ptr_eq(&more.chunks[1].1, &full.chunks[1].1));
        assert!(more.chunks[2].1.capacity() <= 1);
    }
}

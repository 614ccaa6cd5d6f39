//! Names, interned: a [`Name`] is a 4-byte symbol and its span.
//!
//! A large `:init` or a domain of many ground actions holds hundreds of
//! thousands of names, most of them repeated (the same objects, the same
//! predicates). Each distinct text is stored once, for the life of the
//! process, in a table that any thread reads without locking; a name is its
//! index there. Names are compared, hashed and copied as integers; their text
//! and key are `&'static str`.
//!
//! The table only grows: a language server keeps every name it has ever
//! lowered, including those typed half-way. Each distinct text costs about
//! 55 bytes besides its own bytes (its 48-byte slot in the table, its place
//! in the map): a session that types ten thousand names of ten letters,
//! each lowered at every letter, adds about 6 MB.

use std::hash::{BuildHasher, Hasher};
use std::sync::Mutex;

use rowan::TextRange;

use super::Str;

/// A name as written, with its lower-cased key (PDDL names are case-insensitive).
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Name {
    sym: Symbol,
    pub span: TextRange,
}

impl Name {
    #[inline]
    pub fn new(text: &str, span: TextRange) -> Name {
        Name { sym: Symbol::new(text), span }
    }

    /// The name as written.
    #[inline]
    pub fn text(&self) -> &'static str {
        self.sym.entry().text
    }

    /// The name lower-cased: what it is compared and looked up by.
    #[inline]
    pub fn key(&self) -> &'static str {
        self.sym.entry().key
    }

    /// The symbol of [`Name::key`].
    #[inline]
    pub fn key_sym(&self) -> Symbol {
        Symbol(self.sym.entry().key_sym)
    }

    /// [`Name::text`], owned.
    pub fn text_str(&self) -> Str {
        Str::new(self.text())
    }

    /// [`Name::key`], owned.
    pub fn key_str(&self) -> Str {
        Str::new(self.key())
    }
}

impl std::fmt::Debug for Name {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Name")
            .field("text", &self.text())
            .field("key", &self.key())
            .field("span", &self.span)
            .finish()
    }
}

/// A distinct text, interned: its index in the table. Compared and hashed
/// as an integer, ordered by its text, read as a `&'static str`.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Symbol(u32);

impl Symbol {
    #[inline]
    pub fn as_str(self) -> &'static str {
        self.entry().text
    }
}

impl std::ops::Deref for Symbol {
    type Target = str;
    #[inline]
    fn deref(&self) -> &'static str {
        self.as_str()
    }
}

impl From<&str> for Symbol {
    fn from(text: &str) -> Symbol {
        Symbol::new(text)
    }
}

impl From<String> for Symbol {
    fn from(text: String) -> Symbol {
        Symbol::new(&text)
    }
}

impl AsRef<str> for Symbol {
    fn as_ref(&self) -> &str {
        self.as_str()
    }
}

impl std::borrow::Borrow<str> for Symbol {
    fn borrow(&self) -> &str {
        self.as_str()
    }
}

impl PartialOrd for Symbol {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Symbol {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        if self.0 == other.0 { std::cmp::Ordering::Equal } else { self.as_str().cmp(other.as_str()) }
    }
}

impl PartialEq<str> for Symbol {
    fn eq(&self, other: &str) -> bool {
        self.as_str() == other
    }
}

impl PartialEq<&str> for Symbol {
    fn eq(&self, other: &&str) -> bool {
        self.as_str() == *other
    }
}

impl std::fmt::Debug for Symbol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Debug::fmt(self.as_str(), f)
    }
}

impl std::fmt::Display for Symbol {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// What a symbol stands for: the text as written and its key (the same
/// slice when the text has no upper-case letter, as most names; else the
/// text of the key's own symbol).
struct Entry {
    text: &'static str,
    key: &'static str,
    /// The symbol of `key` (this entry's own when the text is its key).
    key_sym: u32,
}

/// The symbols' entries, by index: pushed under a shard's lock, read without one.
static ENTRIES: boxcar::Vec<Entry> = boxcar::Vec::new();

/// The shards of the text → symbol map: a name is looked up in the shard its
/// hash selects, so that threads lowering different files rarely wait.
const SHARDS: usize = 16;

struct Shard {
    /// Symbols by the hash of their text.
    map: hashbrown::HashTable<u32>,
    /// Where the shard's texts are copied: chunks never freed nor moved.
    chunk: &'static mut [u8],
}

static MAP: [Mutex<Shard>; SHARDS] =
    [const { Mutex::new(Shard { map: hashbrown::HashTable::new(), chunk: &mut [] }) }; SHARDS];

/// Texts are copied into chunks of this size (longer ones get their own).
const CHUNK: usize = 16 * 1024;

fn hash(text: &str) -> u64 {
    let mut h = rustc_hash::FxBuildHasher.build_hasher();
    h.write(text.as_bytes());
    h.finish()
}

impl Symbol {
    #[inline]
    fn entry(self) -> &'static Entry {
        &ENTRIES[self.0 as usize]
    }

    /// The symbol of `text` (as written: `Rover` and `rover` are two symbols).
    pub fn new(text: &str) -> Symbol {
        let h = hash(text);
        if let Some(sym) = cache::get(h, text) {
            return sym;
        }
        // The key's symbol first, with no lock held (it has no upper case:
        // this recurses once at most).
        let key_sym =
            super::has_ascii_uppercase(text.as_bytes()).then(|| Symbol::new(&text.to_ascii_lowercase()));
        // The top bits choose the shard, the map uses all of them.
        let mut shard = MAP[(h >> 60) as usize % SHARDS].lock().unwrap_or_else(|e| e.into_inner());
        let found = shard.map.find(h, |&i| ENTRIES[i as usize].text == text).copied();
        let index = match found {
            Some(i) => i,
            None => {
                let text = shard.store(text);
                // A text with upper case shares its key's entry's text; one
                // without is its own key, and the entry's index is its key's
                // symbol (read back from the push: other shards push too).
                let key = key_sym.map_or(text, Symbol::as_str);
                let i =
                    ENTRIES.push_with(|i| Entry { text, key, key_sym: key_sym.map_or(i as u32, |k| k.0) });
                let i = u32::try_from(i).expect("fewer than 2^32 distinct names");
                shard.map.insert_unique(h, i, |&i| hash(ENTRIES[i as usize].text));
                i
            }
        };
        let sym = Symbol(index);
        cache::put(h, sym);
        sym
    }
}

impl Shard {
    /// Copies `text` where it stays.
    fn store(&mut self, text: &str) -> &'static str {
        if self.chunk.len() < text.len() {
            let size = text.len().max(CHUNK);
            self.chunk = Box::leak(vec![0u8; size].into_boxed_slice());
        }
        let (bytes, rest) = std::mem::take(&mut self.chunk).split_at_mut(text.len());
        self.chunk = rest;
        bytes.copy_from_slice(text.as_bytes());
        let bytes: &'static [u8] = bytes;
        std::str::from_utf8(bytes).expect("a copy of a str")
    }
}

/// A small per-thread cache of recent symbols by hash, so that the names
/// that repeat (most of them) do not take a lock.
mod cache {
    use std::cell::RefCell;

    use super::{ENTRIES, Symbol};

    const SIZE: usize = 4096;

    thread_local! {
        static CACHE: RefCell<Box<[(u64, u32)]>> = RefCell::new(vec![(0, u32::MAX); SIZE].into_boxed_slice());
    }

    #[inline]
    pub(super) fn get(h: u64, text: &str) -> Option<Symbol> {
        CACHE
            .try_with(|c| {
                let (hh, i) = c.borrow()[h as usize % SIZE];
                (hh == h && i != u32::MAX && ENTRIES[i as usize].text == text).then_some(Symbol(i))
            })
            .ok()
            .flatten()
    }

    #[inline]
    pub(super) fn put(h: u64, sym: Symbol) {
        let _ = CACHE.try_with(|c| c.borrow_mut()[h as usize % SIZE] = (h, sym.0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span() -> TextRange {
        TextRange::default()
    }

    #[test]
    fn the_same_text_is_the_same_symbol_and_case_makes_another() {
        let a = Name::new("Rover1", span());
        let b = Name::new("Rover1", span());
        let c = Name::new("rover1", span());
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(a.text(), "Rover1");
        assert_eq!(a.key(), "rover1");
        assert_eq!(c.text(), "rover1");
        assert_eq!(c.key(), "rover1");
        assert_eq!(a.key(), c.key());
    }

    #[test]
    fn names_interned_on_many_threads_agree() {
        let texts: Vec<String> = (0..2000).map(|i| format!("Obj-{i}-ÉTÉ")).collect();
        let syms: Vec<Vec<Name>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..4)
                .map(|_| s.spawn(|| texts.iter().map(|t| Name::new(t, span())).collect::<Vec<_>>()))
                .collect();
            handles.into_iter().map(|h| h.join().unwrap()).collect()
        });
        for names in &syms[1..] {
            assert_eq!(names, &syms[0]);
        }
        for (n, t) in syms[0].iter().zip(&texts) {
            assert_eq!(n.text(), t);
            assert_eq!(n.key(), t.to_ascii_lowercase());
        }
    }

    #[test]
    fn long_names_and_the_empty_name_are_kept_whole() {
        let long = "x".repeat(3 * CHUNK);
        assert_eq!(Name::new(&long, span()).text(), long);
        assert_eq!(Name::new("", span()).text(), "");
        assert_eq!(Name::new("", span()).key(), "");
    }
}

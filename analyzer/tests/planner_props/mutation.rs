//! Random mutations of a problem's text that mostly keep it well formed:
//! unbalanced parentheses, unknown names, unsupported constructs.

use hipop_analyzer::{TextEdit, TextRange, TextSize};
use proptest::prelude::*;

pub(crate) const PIECES: &[&str] = &[
    "(",
    ")",
    " ",
    "(zz ?x0)",
    "(p9)",
    "?x7",
    "o9",
    "t5",
    "(not",
    "(or (p0) (p1))",
    "(forall (?y - t0) (p0 ?y))",
    "(when (p0) (p1))",
    "(at start (p0))",
    "(at end (not (p1)))",
    "(over all (p1))",
    "(= ?duration 0)",
    "(at 3 (p0))",
    "(increase (total-cost) 1)",
    ":action",
    ":durative-action",
    "- t1",
    "-1",
];

#[derive(Debug, Clone)]
pub(crate) enum Mutation {
    Delete(usize, usize),
    Insert(usize, usize),
    Duplicate(usize, usize, usize),
    /// Replaces an occurrence of `SWAPS[k].0` (the `n`-th, cyclically) by `SWAPS[k].1`.
    Swap(usize, usize),
}

/// Replacements that mostly keep the text well formed.
pub(crate) const SWAPS: &[(&str, &str)] = &[
    ("at start", "at end"),
    ("at end", "over all"),
    ("over all", "at start"),
    ("(not ", "(and "),
    ("p0", "p1"),
    ("p1", "p2"),
    ("p2", "p0"),
    ("o0", "o1"),
    ("?x0", "?x1"),
    ("t1", "t0"),
    ("t0", "t1"),
    ("?duration 1", "?duration 0"),
    (":action", ":durative-action"),
    ("(:init", "(:init (at 2 (p0)) (at 4 (not (p1)))"),
    ("(:goal (and", "(:goal (and (p3)"),
    ("(and ", "(and (at start (not (p0))) "),
    ("(:allowed-actions", "(:allowed-actions a9"),
];

pub(crate) fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        1 => (any::<usize>(), 0usize..20).prop_map(|(a, n)| Mutation::Delete(a, n)),
        1 => (any::<usize>(), 0..PIECES.len()).prop_map(|(a, p)| Mutation::Insert(a, p)),
        1 => (any::<usize>(), 0usize..60, any::<usize>()).prop_map(|(a, n, b)| Mutation::Duplicate(a, n, b)),
        3 => (0..SWAPS.len(), any::<usize>()).prop_map(|(k, n)| Mutation::Swap(k, n)),
    ]
}

pub(crate) fn mutate(text: &mut String, m: &Mutation) {
    let at = |x: usize| x % (text.len() + 1);
    let (start, end, insert) = match *m {
        Mutation::Delete(a, n) => {
            let s = at(a);
            (s, (s + n).min(text.len()), String::new())
        }
        Mutation::Insert(a, p) => (at(a), at(a), PIECES[p].to_string()),
        Mutation::Duplicate(a, n, b) => {
            let s = at(a);
            let e = (s + n).min(text.len());
            (at(b), at(b), text[s..e].to_string())
        }
        Mutation::Swap(k, n) => {
            let (from, to) = SWAPS[k];
            let found: Vec<usize> = text.match_indices(from).map(|(i, _)| i).collect();
            if found.is_empty() {
                return;
            }
            let s = found[n % found.len()];
            (s, s + from.len(), to.to_string())
        }
    };
    TextEdit { range: TextRange::new(TextSize::from(start as u32), TextSize::from(end as u32)), insert }
        .apply(text);
}

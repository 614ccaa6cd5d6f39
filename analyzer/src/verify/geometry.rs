//! The pure geometry of move actions (Definition 14 of the HiPOP paper): which
//! predicates may be position families, and which moves break the triangle
//! inequality. No database here: the lints feed these functions.

use crate::model::Str;

use super::lifted::Operator;

/// A candidate position family, lifted: predicate `pred` whose argument `pos`
/// is the position and whose other arguments say whose position it is
/// (`at-r ?r *` is `pred = at-r, pos = 1`).
///
/// `key_type` restricts a predicate of two arguments to the keys of one type
/// (`at ?truck *`: the `at` of trucks): a predicate that several types share
/// (DriverLog's `at` of drivers, trucks and packages) may be a family for
/// one of them only.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Candidate {
    pub pred: Str,
    pub arity: u32,
    pub pos: u32,
    pub key_type: Option<Str>,
}

/// The candidates a domain's operators suggest: an operator that deletes
/// `(p a₁ … aₙ)` and adds `(p b₁ … bₙ)` where the arguments differ in exactly
/// one place changes "where" something is. Predicates nothing moves that way
/// cannot be families (Definition 12 needs an action that replaces one member
/// by another), so they are not candidates.
pub fn candidates<'a>(operators: impl IntoIterator<Item = &'a Operator>) -> Vec<Candidate> {
    let mut out: Vec<Candidate> = Vec::new();
    for op in operators {
        for del in &op.del {
            for add in op.add.iter().filter(|a| a.pred == del.pred && a.args.len() == del.args.len()) {
                let mut differ = add.args.iter().zip(&del.args).enumerate().filter(|(_, (a, d))| a != d);
                let (Some((pos, _)), None) = (differ.next(), differ.next()) else { continue };
                let candidate = Candidate {
                    pred: Str::new(del.pred),
                    arity: del.args.len() as u32,
                    pos: pos as u32,
                    key_type: None,
                };
                if !out.contains(&candidate) {
                    out.push(candidate);
                }
            }
        }
    }
    out
}

/// A move that is slower than going through another position:
/// `dur(from → to) > dur(from → via) + dur(via → to)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detour {
    pub from: u32,
    pub via: u32,
    pub to: u32,
    /// `dur(from → to)`.
    pub direct: f64,
    pub first: f64,
    pub second: f64,
}

/// The pairs `(from, to)` whose direct move is slower, by more than
/// `tolerance`, than the fastest detour through one other position; one
/// [`Detour`] per pair, with that fastest detour, in `(from, to)` order.
///
/// `dur` is the `n × n` matrix of move durations, row `from`, column `to`;
/// infinity where there is no move. This is the inequality as the paper's text
/// means it ("a succession of actions cannot be faster than a single move
/// action"): property 6 of Definition 14 prints it the other way round.
///
/// Only the moves that exist are visited: `O(Σ deg(f)²)` over the out-degrees,
/// which is `O(n³)` for a complete map (80 positions, 512,000 triples) and
/// much less for a sparse one (thousands of waypoints linked to neighbours).
pub fn detours(n: usize, d: &[f64], tolerance: f64) -> Vec<Detour> {
    assert_eq!(d.len(), n * n, "a square matrix");
    let mut out = Vec::new();
    let mut next: Vec<usize> = Vec::new();
    for from in 0..n {
        let row = &d[from * n..(from + 1) * n];
        next.clear();
        next.extend((0..n).filter(|&v| v != from && row[v].is_finite()));
        for &to in &next {
            let direct = row[to];
            let mut best = (f64::INFINITY, usize::MAX);
            for &via in &next {
                let through = row[via] + d[via * n + to];
                if via != to && through < best.0 {
                    best = (through, via);
                }
            }
            let (through, via) = best;
            if through.is_finite() && direct > through + tolerance {
                out.push(Detour {
                    from: from as u32,
                    via: via as u32,
                    to: to as u32,
                    direct,
                    first: row[via],
                    second: d[via * n + to],
                });
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn matrix(dur: &[Option<f64>]) -> Vec<f64> {
        dur.iter().map(|d| d.unwrap_or(f64::INFINITY)).collect()
    }

    #[test]
    fn euclidean_distances_have_no_detour() {
        let pts = [(0.0, 0.0), (3.0, 0.0), (3.0, 4.0), (10.0, 1.0)];
        let n = pts.len();
        let dur: Vec<Option<f64>> = (0..n * n)
            .map(|i| {
                let (a, b) = (pts[i / n], pts[i % n]);
                Some(f64::hypot(a.0 - b.0, a.1 - b.1))
            })
            .collect();
        assert_eq!(detours(n, &matrix(&dur), 1e-9), vec![]);
    }

    #[test]
    fn a_slow_direct_move_is_found_with_its_fastest_detour() {
        // 0 → 2 takes 10, but 0 → 1 → 2 takes 3 + 4 = 7: the paper's printed
        // inequality (3 + 4 ≤ 10) holds, the intended one (10 ≤ 3 + 4) does not.
        let x = None;
        #[rustfmt::skip]
        let dur = [
            Some(0.0), Some(3.0), Some(10.0),
            Some(3.0), Some(0.0), Some(4.0),
            x,         Some(4.0), Some(0.0),
        ];
        let found = detours(3, &matrix(&dur), 0.01);
        assert_eq!(found.len(), 1);
        let d = found[0];
        assert_eq!((d.from, d.via, d.to), (0, 1, 2));
        assert_eq!((d.direct, d.first, d.second), (10.0, 3.0, 4.0));
        // Within the tolerance, no warning.
        assert_eq!(detours(3, &matrix(&dur), 3.5), vec![]);
    }

    #[test]
    fn missing_moves_are_not_detours() {
        let dur = [Some(0.0), None, Some(5.0), None, Some(0.0), Some(1.0), Some(1.0), Some(1.0), Some(0.0)];
        // 0 → 2 direct 5; via 1: 0 → 1 missing.
        assert!(detours(3, &matrix(&dur), 0.0).iter().all(|d| !(d.from == 0 && d.to == 2)));
    }

    #[test]
    fn candidates_come_from_moves() {
        let ops = crate::verify::lifted::tests_support::operators(
            "(define (domain d) (:predicates (at ?r ?w) (holding ?r ?o) (free ?r))
              (:action move :parameters (?r ?a ?b)
               :precondition (at ?r ?a) :effect (and (not (at ?r ?a)) (at ?r ?b)))
              (:action pick :parameters (?r ?o)
               :precondition (free ?r) :effect (and (not (free ?r)) (holding ?r ?o))))",
        );
        assert_eq!(candidates(&ops), vec![Candidate { pred: "at".into(), arity: 2, pos: 1, key_type: None }]);
    }
}

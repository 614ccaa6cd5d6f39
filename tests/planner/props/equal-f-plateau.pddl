; Found by analyzer/tests/planner_props.rs with HIPOP_PROPS_STRICT=1 (a limit
; where the breadth-first search finds a plan, shrunk).
; expect: solved
; fixed: ties on f go to the smaller plan before the newest (planner/search.rs,
; `Ord for Node`); the description below is of the bug.
;
; `0.000: (a0 o0) [1.000]` is a plan (`p1` from the initial state). The
; planner (AR-time-local-motion, AR-time-local-ncm, R-time-local, bare) stops
; at its time limit after a few hundred expansions, best f stuck at 1.0:
; every instance of the instantaneous `a1` fits inside `a0` (after its start,
; which gives `p0`, before its end), so inserting one more `a1` to support
; `p1` costs nothing (makespan 1, reuse h 0). All these plans tie on f, and
; the newest node wins ties (search.rs, `Ord for Node`: `self.id.cmp(&other.id)`),
; so the search dives depth-first along an endless chain of `a1`s (about a
; hundred fit in 1.0 at 0.01 apart, and each expansion gets slower as the
; plan grows) instead of returning to the sibling that links `p1` to the
; initial state. time-threatFirst solves it in a few expansions.
(define (domain d)
  (:requirements :strips :typing :durative-actions)
  (:types t0 - object)
  (:predicates (p0) (p1) (p2 ?v0 - t0))
  (:durative-action a0
    :parameters (?x0 - t0)
    :duration (= ?duration 1)
    :condition (and (at end (p1)))
    :effect (and (at start (p2 ?x0)) (at start (p0))))
  (:action a1
    :parameters ()
    :precondition (and (p1) (p0))
    :effect (and (p1))))

(define (problem pr)
  (:domain d)
  (:objects o0 - t0 o1 - t0)
  (:init (p1))
  (:goal (p2 o0)))

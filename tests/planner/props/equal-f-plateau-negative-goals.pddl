; Found by analyzer/tests/planner_props.rs with HIPOP_PROPS_STRICT=1
; HIPOP_PROPS_SEED=7 (configuration bare; shrunk).
; expect: solved
; fixed: ties on f go to the smaller plan before the newest (planner/search.rs,
; `Ord for Node`); the description below is of the bug.
;
; The same plateau as equal-f-plateau.pddl, with goals that hold initially:
; `0.000: (a0) [3.000]` is a plan (`(not (p0 o0))` and `(p2)` hold in the
; initial state). Instances of the instantaneous `a1`, which needs and adds
; `p2`, fit inside `a0` at no cost, each needing another one or the initial
; state for `p2`; the search stops at its time limit.
(define (domain d)
  (:requirements :strips :typing :negative-preconditions :durative-actions)
  (:types t0 - object)
  (:predicates (p0 ?v0 - t0) (p1) (p2))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 3)
    :condition (and)
    :effect (and (at start (not (p1)))))
  (:action a1
    :parameters (?x0 - t0)
    :precondition (and (p2))
    :effect (and (not (p0 ?x0)) (p2))))

(define (problem pr)
  (:domain d)
  (:objects o0 - t0 o1 - t0)
  (:init (p2) (p1))
  (:goal (and (not (p1)) (not (p0 o0)) (p2))))

; Companion of over-all-supported-by-own-start.pddl (analyzer/tests/planner_props.rs).
; expect: solved
; fixed: ties on f go to the smaller plan before the newest (planner/search.rs,
; `Ord for Node`); the description below is of the bug.
;
; `a0` deletes `p1` at its start and needs `(not (p1))` at its end: `0.000: (a0) [1.000]`
; is valid.
(define (domain d)
  (:requirements :strips :negative-preconditions :durative-actions)
  (:predicates (p0) (p1))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and (at end (not (p1))))
    :effect (and (at start (not (p1))) (at end (p0)))))

(define (problem pr)
  (:domain d)
  (:init (p1))
  (:goal (p0)))

; Companion of over-all-supported-by-own-start.pddl (analyzer/tests/planner_props.rs).
; expect: solved
; fixed: the STRIPS view leaves out of `Pre` what the action's own start makes
; true (verify/lifted.rs), so relaxed reachability reaches the goal; the
; description below is of the bug.
;
; `a0` adds `p1` at its start and needs it at its end: `0.000: (a0) [1.000]`
; is valid.
(define (domain d)
  (:requirements :strips :durative-actions)
  (:predicates (p0) (p1))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and (at end (p1)))
    :effect (and (at start (p1)) (at end (p0)))))

(define (problem pr)
  (:domain d)
  (:init)
  (:goal (p0)))

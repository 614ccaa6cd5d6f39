; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs).
; expect: solved
; fixed: the STRIPS view leaves out of `Pre` what the action's own start makes
; true (verify/lifted.rs), so relaxed reachability reaches the goal; the
; description below is of the bug.
;
; The positive twin of over-all-supported-by-own-start.pddl: `a0` adds `p1`
; at its start and needs it over all; `0.000: (a0) [1.000]` is valid (the
; `over all` interval is open, after the start's effects).
(define (domain d)
  (:requirements :strips :durative-actions)
  (:predicates (p0) (p1))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and (over all (p1)))
    :effect (and (at start (p1)) (at end (p0)))))

(define (problem pr)
  (:domain d)
  (:init)
  (:goal (p0)))

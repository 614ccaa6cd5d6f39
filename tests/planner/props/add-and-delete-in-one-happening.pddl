; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs).
; expect: no-plan
;
; The end of `a0` both adds and deletes `p0`. VAL's semantics (and the
; validator's) apply deletions before additions: `p0` stays true, so no plan
; reaches the goal `(not p0)`. The planner takes the deletion as a support
; of `(not (p0))` and returns `0.000: (a0) [1.000]`, which the validator rejects:
;   E0419 goal-not-reached: the goal is not reached at the end of the plan
;   (1.0): `(p0)` is true: added at 1.0 by the end of the step on line 1
;   `(a0)`
; (A deletion at a time point where the same step adds the atom has no
; effect: it should neither support `(not p)` nor threaten `p`.)
(define (domain d)
  (:requirements :strips :typing :negative-preconditions :durative-actions)
  (:predicates (p0))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and)
    :effect (and (at end (p0)) (at end (not (p0))))))

(define (problem pr)
  (:domain d)
  (:init (p0))
  (:goal (not (p0))))

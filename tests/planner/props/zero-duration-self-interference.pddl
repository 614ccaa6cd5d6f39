; Found by analyzer/tests/planner_props.rs (mutated_problems_never_panic: a
; mutation set a duration to 0), reduced by hand.
; expect: no-plan
;
; `a0` lasts 0: its start and its end are one happening, where its start adds
; `p2` and its end deletes it, a mutex (VAL and the validator reject every
; plan with `a0`, so there is no plan for the goal `(not (p0))`). The
; planner returns `0.000: (a0) [0.000]`, which the validator rejects:
;   E0418 mutex-happenings: the step on line 1 `(a0)`, ending at 0.0
;   interferes with the start of the step on line 1 `(a0)` at 0.0: the start
;   of the step on line 1 adds `(p2)`, which the end of the step on line 1
;   deletes
; (Either refuse durative actions of duration 0 (E0501), or treat a step's
; own start and end as interfering events when they coincide.)
(define (domain d)
  (:requirements :strips :negative-preconditions :durative-actions)
  (:predicates (p0) (p2))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 0)
    :condition (and)
    :effect (and (at start (p2)) (at end (not (p2))) (at end (not (p0))))))

(define (problem pr)
  (:domain d)
  (:init (p0))
  (:goal (not (p0))))

; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs).
; expect: solved
;
; `a0` deletes `p2` at its start and needs `(not (p2))` over all. In PDDL 2.1
; (and for VAL and the validator) an `over all` condition must hold in the
; open interval between the start and the end: after the start's effects.
; `0.000: (a0) [1.000]` is a valid plan. The planner treats `over all` as
; needed from the start point on (planner/task.rs: `Cond { at: Start, until:
; End }`), finds that nothing but `a0` itself can support `(not (p2))` and
; says:
;   E0502 no-plan: no plan with the allowed actions and the methods: the
;   search explored every partial plan (1 expanded)
;   I0504 open-link: open link: (p0) for the goal: no allowed action achieves
;   it, even ignoring deletions
(define (domain d)
  (:requirements :strips :negative-preconditions :durative-actions)
  (:predicates (p0) (p2))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and (over all (not (p2))))
    :effect (and (at start (not (p2))) (at end (p0)))))

(define (problem pr)
  (:domain d)
  (:init (p2))
  (:goal (p0)))

; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs).
; expect: no-plan
;
; `p1` is static: no action changes it. The goal `(p1 o0)` is false in the
; initial state, so no plan exists: the planner must say so (no plan, or a
; refusal naming the goal atom that no action can make true). It returns the
; empty plan instead, which the validator rejects:
;   E0419 goal-not-reached: the goal is not reached at the end of the plan
;   (0.0): `(p1 o0)` is false: it is not in the initial state and nothing
;   makes it true before
; (planner/task.rs: `Compiler::atom` returns `Ok(None)` for a static atom,
; "grounding checked it", so `conds` drops the goal literal; grounding checks
; the static conditions of actions, not those of the goal.)
(define (domain d)
  (:requirements :strips :typing :negative-preconditions :durative-actions)
  (:types t0 - object)
  (:predicates (p0) (p1 ?v0 - t0))
  (:durative-action a0
    :parameters ()
    :duration (= ?duration 1)
    :condition (and)
    :effect (and (at start (p0)))))

(define (problem pr)
  (:domain d)
  (:objects o0 - t0 o1 - t0)
  (:init (p0))
  (:goal (and (p1 o0))))

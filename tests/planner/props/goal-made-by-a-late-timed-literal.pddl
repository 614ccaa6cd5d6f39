; Found by analyzer/tests/planner_props.rs (mutated_problems_never_panic,
; 3,000 cases, seed 20261124): a plan the validator rejects.
; expect: solved
;
; The goal `(p0)` becomes true at 2 by a timed initial literal, and the
; empty plan looked like a solution. VAL applies no timed literal after the
; plan's last event, so the goal is false at the end of the empty plan. A
; step must end after the literal: `a3` (no conditions) does.
(define (domain d)
  (:requirements :strips :typing :durative-actions :timed-initial-literals)
  (:types t0)
  (:predicates (p0) (p1))
  (:durative-action a3
    :parameters (?x0 - t0)
    :duration (= ?duration 4)
    :condition (and)
    :effect (and (at start (p1)))))

(define (problem pr)
  (:domain d)
  (:objects o0 - t0)
  (:init (at 2 (p0)))
  (:goal (and (p0))))

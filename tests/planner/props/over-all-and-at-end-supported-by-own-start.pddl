; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs,
; 1,000 cases, seed 1): "no plan" where the breadth-first search found one.
; expect: solved
;
; `a0` adds `(p1 o0)` at its start and needs it over all and at its end:
; `0.000: (a0 o0) [1.000]` is valid. The two conditions on one literal are
; one open link (the widest protection); merging the `at end` one made it
; needed *at* the start, where the step's own start effect cannot support
; it, so every plan died (or, in other configurations, a second `a0` was
; inserted for it, and a third for that one, until the time limit).
(define (domain d)
  (:requirements :strips :typing :negative-preconditions :durative-actions)
  (:types t0)
  (:predicates (p1 ?v0 - t0))
  (:durative-action a0
    :parameters (?x0 - t0)
    :duration (= ?duration 1)
    :condition (and (over all (p1 ?x0)) (at start (not (p1 ?x0))) (at end (p1 ?x0)))
    :effect (and (at start (p1 ?x0)))))

(define (problem pr)
  (:domain d)
  (:objects o0 - t0)
  (:goal (and (p1 o0))))

; Found by analyzer/tests/planner_props.rs (random_problems_against_the_validator_and_bfs,
; 3,000 cases): a limit where the breadth-first search found a plan.
; expect: solved
;
; `0.000: (a2 o0) [4.000]` is a plan. `(a1 o0 o0)` (2 s) looks cheaper for
; the goal, but it adds `(p0 o0 o0)` at its start and needs it false at its
; end, which nothing can do. Every further `a1` inserted for its conditions
; fits in parallel (no longer makespan) and reuse makes its own conditions
; free: an endless subtree of plans of f = 2, which A* never leaves for the
; f = 4 of `a2`. Each step now costs a little in g (planner/search.rs,
; `STEP_COST`), so the subtree's f grows until `a2` is tried.
(define (domain d)
  (:requirements :strips :typing :negative-preconditions :durative-actions)
  (:types t0 - object)
  (:predicates (p0 ?v0 - t0 ?v1 - t0) (p1 ?v0 - t0) (p2 ?v0 - t0))
  (:action a0
    :parameters ()
    :precondition (and )
    :effect (and ))
  (:durative-action a1
    :parameters (?x0 - t0 ?x1 - t0)
    :duration (= ?duration 2)
    :condition (and (at end (not (p0 ?x0 ?x0))) (at end (p2 ?x1)))
    :effect (and (at start (p2 ?x0)) (at start (p1 ?x1)) (at start (p0 ?x1 ?x1))))
  (:durative-action a2
    :parameters (?x0 - t0)
    :duration (= ?duration 4)
    :condition (and (over all (not (p0 ?x0 ?x0))))
    :effect (and (at end (p0 ?x0 ?x0)) (at end (not (p2 ?x0)))))
  (:durative-action a3
    :parameters (?x0 - t0 ?x1 - t0)
    :duration (= ?duration 5)
    :condition (and (over all (not (p2 ?x0))))
    :effect (and (at end (p0 ?x1 ?x1))))
)
(define (problem pr)
  (:domain d)
  (:objects o0 - t0 o1 - t0)
  (:init (p1 o1) (p2 o1))
  (:goal (and (p0 o0 o0))))

; The duration of `move` reads `(distance ?from ?to)`, which the problem
; gives for a-c and c-b but not for the road a-b: in PDDL 2.1 the move a → b
; is not applicable (I0306), and the rover goes through c. Before, the
; planner refused the whole problem (E0501, "a duration that is not one
; number").
(define (domain roads)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types rover waypoint)
  (:predicates (at ?r - rover ?w - waypoint) (road ?from ?to - waypoint))
  (:functions (distance ?from ?to - waypoint))
  (:durative-action move
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration (distance ?from ?to))
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))
(define (problem through-c)
  (:domain roads)
  (:objects r1 - rover a b c - waypoint)
  (:init
    (at r1 a)
    (road a b) (road a c) (road c b)
    (= (distance a c) 10)
    (= (distance c b) 12))
  (:goal (at r1 b)))

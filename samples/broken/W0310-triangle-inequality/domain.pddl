; W0310 triangle-inequality: see the problem.
(define (domain rovers-geo)
  (:requirements :typing :durative-actions :numeric-fluents :equality :negative-preconditions)
  (:types robot waypoint)
  (:predicates (at ?r - robot ?w - waypoint))
  (:functions (distance ?a ?b - waypoint))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration (distance ?from ?to))
    :condition (and (at start (at ?r ?from)) (over all (not (= ?from ?to))))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))

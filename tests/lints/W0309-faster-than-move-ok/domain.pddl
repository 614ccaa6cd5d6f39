; `jump` takes 20: slower than any move, so moves stay lower bounds.
(define (domain rovers-geo)
  (:requirements :typing :durative-actions :numeric-fluents :equality :negative-preconditions)
  (:types robot waypoint)
  (:predicates (at ?r - robot ?w - waypoint) (charged ?r - robot))
  (:functions (distance ?a ?b - waypoint))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration (distance ?from ?to))
    :condition (and (at start (at ?r ?from)) (over all (not (= ?from ?to))))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to))))
  (:durative-action jump
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration 20)
    :condition (and (at start (at ?r ?from)) (at start (charged ?r)) (over all (not (= ?from ?to))))
    :effect (and (at start (not (at ?r ?from))) (at start (not (charged ?r))) (at end (at ?r ?to)))))

; I0307 not-a-position-family: `at ? *` looks like the position of a robot
; (`move` replaces one `at` by another), but `r2` has no position in the
; initial state (property 1 of Definition 12). hipop does not use the
; position reasoning of the paper for `at`. Give `r2` a position, or silence
; with `; hipop-allow-file: I0307` in the problem.
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

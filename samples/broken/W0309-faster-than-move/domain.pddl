; W0309 faster-than-move: `jump` changes the position of a robot in 1, faster
; than the move action `move` between the same waypoints (3 or more). Move
; durations are then no lower bound of the time between two positions. Make
; `jump` take at least as long as the move, or silence with
; `; hipop-allow: W0309` on its line.
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
    :duration (= ?duration 1)
    :condition (and (at start (at ?r ?from)) (at start (charged ?r)) (over all (not (= ?from ?to))))
    :effect (and (at start (not (at ?r ?from))) (at start (not (charged ?r))) (at end (at ?r ?to)))))

; I0308 missing-move: `move` needs `(adjacent ?from ?to)`, and `a` and `c`
; are not adjacent: no move action goes directly between them (property 4 of
; Definition 14). This is information: the planner goes through `b`. Add the
; moves if direct trips exist, or silence with `; hipop-allow-file: I0308`.
(define (domain rovers-geo)
  (:requirements :typing :durative-actions :numeric-fluents :equality :negative-preconditions)
  (:types robot waypoint)
  (:predicates (at ?r - robot ?w - waypoint) (adjacent ?a ?b - waypoint))
  (:functions (distance ?a ?b - waypoint))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration (distance ?from ?to))
    :condition (and (at start (at ?r ?from)) (over all (adjacent ?from ?to)) (over all (not (= ?from ?to))))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))

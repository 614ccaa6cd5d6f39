; W0203 missing-requirement: `move` is a durative action, but `:requirements`
; does not declare `:durative-actions`. Planners that check requirements reject
; the domain.
; Fix: add `:durative-actions` to `(:requirements …)` (hipop offers the edit).
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:durative-action move
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration 10)
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))

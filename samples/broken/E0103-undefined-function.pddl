; E0103 undefined-function: the effect of `move` increases `(odometer ?r)` by
; `(distanse ?from ?to)`, but the function is declared as `distance`.
; Fix: correct the name (hipop suggests `distance`), or declare the function in
; `(:functions …)`.
(define (domain rovers)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types rover waypoint)
  (:predicates (at ?r - rover ?w - waypoint))
  (:functions
    (distance ?from ?to - waypoint) - number
    (speed ?r - rover) - number
    (odometer ?r - rover) - number)

  (:durative-action move
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration (/ (distance ?from ?to) (speed ?r)))
    :condition (at start (at ?r ?from))
    :effect (and
      (at start (not (at ?r ?from)))
      (at end (at ?r ?to))
      (at end (increase (odometer ?r) (distanse ?from ?to))))))

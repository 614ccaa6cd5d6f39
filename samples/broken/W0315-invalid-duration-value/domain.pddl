; W0315 invalid-duration-value, domain: correct. The duration of `move` is
; `(distance ?from ?to)` divided by `(speed ?r)`: it is negative when a
; problem gives a negative distance.
(define (domain rover-moves)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))
  (:functions
    (distance ?from ?to - waypoint)
    (speed ?r - rover))

  (:durative-action move
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration (/ (distance ?from ?to) (speed ?r)))
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))

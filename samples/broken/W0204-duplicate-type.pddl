; W0204 duplicate-type: `rover` is declared twice in `(:types …)`. Real domains
; do this, so it is a warning; the parents of both declarations are merged.
; Fix: keep one declaration of `rover`.
(define (domain rovers)
  (:requirements :typing)
  (:types
    robot waypoint - object
    rover - robot
    rover - robot)
  (:predicates
    (at ?r - robot ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

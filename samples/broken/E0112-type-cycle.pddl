; E0112 type-cycle: `rover` is a `vehicle` and `vehicle` is a `rover`: the
; type hierarchy loops, so neither has `object` as a well-defined ancestor.
; Fix: remove one of the two parents (here `vehicle` should be `- object`).
(define (domain rovers)
  (:requirements :typing)
  (:types
    rover - vehicle
    vehicle - rover
    waypoint)
  (:predicates
    (at ?v - vehicle ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

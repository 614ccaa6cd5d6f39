; E0101 undefined-type: the parameter `?to` of `move` has the type `waypont`,
; which `(:types …)` does not declare (a typo of `waypoint`).
; Fix: use a declared type (hipop suggests `waypoint`), or declare the type.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from - waypoint ?to - waypont)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

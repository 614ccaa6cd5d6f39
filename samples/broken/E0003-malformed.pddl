; E0003 malformed: `not` takes one atom, but the effect of `move` gives it two:
; `(not (at ?r ?from) (at ?r ?to))` was meant as two effects.
; Fix: `:effect (and (not (at ?r ?from)) (at ?r ?to))`.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (not (at ?r ?from) (at ?r ?to))))

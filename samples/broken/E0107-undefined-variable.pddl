; E0107 undefined-variable: the effect of `move` uses `?dest`, which is neither
; a parameter of `move` nor bound by `forall`/`exists`.
; Fix: use the parameter (`?to`), or add `?dest` to `:parameters`.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?dest))))

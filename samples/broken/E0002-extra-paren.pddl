; E0002 extra-paren: the effect of `move` ends with one `)` too many, which
; closes the whole `define` before `observe`. hipop reports that `)` and keeps
; `observe` in the domain.
; Fix: delete the extra `)` (count the parentheses of the effect).
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (observed ?w - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

  (:action observe
    :parameters (?r - rover ?w - waypoint)
    :precondition (at ?r ?w)
    :effect (observed ?w)))

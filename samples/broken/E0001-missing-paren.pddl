; E0001 missing-paren: the action `move` is not closed: its last `)` is missing
; before `(:action observe`. hipop reports it once, at the end of `move`, and
; still reads `observe` as a section of the domain.
; Fix: add the missing `)` at the end of `move`.
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
    :effect (and (not (at ?r ?from)) (at ?r ?to))

  (:action observe
    :parameters (?r - rover ?w - waypoint)
    :precondition (at ?r ?w)
    :effect (observed ?w)))

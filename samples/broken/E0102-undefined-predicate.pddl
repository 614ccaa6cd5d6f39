; E0102 undefined-predicate: `transmit` requires `(observd ?t)`, but the
; predicate is declared as `observed`.
; Fix: correct the name (hipop suggests `observed`), or declare the predicate.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint target)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (observed ?t - target)
    (transmitted ?t - target))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (at ?r ?w)
    :effect (observed ?t))

  (:action transmit
    :parameters (?r - rover ?t - target)
    :precondition (observd ?t)
    :effect (transmitted ?t)))

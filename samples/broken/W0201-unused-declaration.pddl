; W0201 unused-declaration: the predicate `charged` is declared but no action,
; task, method or problem uses it. A leftover, or a condition someone forgot
; to write.
; Fix: use it where it was meant (e.g. a precondition of `move`), or delete it.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (charged ?r - rover))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

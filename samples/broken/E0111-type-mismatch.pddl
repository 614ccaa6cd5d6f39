; E0111 type-mismatch: `observe` passes its target `?t` where `at` expects a
; waypoint (the arguments of `at` are swapped with those of `visible`).
; Fix: pass an argument of the declared type: `(at ?r ?w)`.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint target)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (visible ?t - target ?w - waypoint)
    (observed ?t - target))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (and (at ?r ?t) (visible ?t ?w))
    :effect (observed ?t)))

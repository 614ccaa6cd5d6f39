; Recovery: an extra `)` before `:effect`. The precondition of `move` closes
; one list too many, which would end the action before its effect; hipop
; reports that `)` alone, keeps the effect in `move`, and still reports the
; undefined predicate `calibrated` in `observe`.
; expect-syntax-error-line: 17
; expect-later-error: E0102 at line 22
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint target)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (observed ?t - target))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to)))
    :effect (and (not (at ?r ?from)) (at ?r ?to)))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (and (at ?r ?w) (calibrated ?r))
    :effect (observed ?t)))

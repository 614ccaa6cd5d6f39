; Recovery: a missing `)` inside a formula followed by a field keyword. The
; `(and …` of the precondition of `move` is not closed; `:effect` belongs to
; the action, so the formula ends before it. The undefined predicate `calibrated`
; in `observe` is still reported.
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
    :precondition (and (at ?r ?from) (road ?from ?to)
    :effect (and (not (at ?r ?from)) (at ?r ?to)))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (and (at ?r ?w) (calibrated ?r))
    :effect (observed ?t)))

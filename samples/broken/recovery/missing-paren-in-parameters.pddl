; Recovery: a missing `)` in the middle of an action. The parameter list of
; `move` is not closed; the field keyword `:precondition` that follows tells
; hipop where it should have ended, and the rest of the file is analysed as
; written: `observe` below still gets its undefined-predicate error (`calibrated`).
; expect-syntax-error-line: 16
; expect-later-error: E0102 at line 22
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint target)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (observed ?t - target))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to)))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (and (at ?r ?w) (calibrated ?r))
    :effect (observed ?t)))

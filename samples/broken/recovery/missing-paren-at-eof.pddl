; Recovery: the `)` that closes the `define` is missing at the end of the file.
; hipop reports it at the last token and analyses the whole domain, including
; the undefined predicate `calibrated` in `observe`.
; expect-syntax-error-line: 22
; expect-later-error: E0102 at line 21
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint target)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (observed ?t - target))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to)))

  (:action observe
    :parameters (?r - rover ?w - waypoint ?t - target)
    :precondition (and (at ?r ?w) (calibrated ?r))
    :effect (observed ?t))

; E0110 wrong-arity: the predicate `at` takes a rover and a waypoint, but the
; effect of `move` gives it one argument.
; Fix: pass every argument: `(at ?r ?to)`.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?to))))

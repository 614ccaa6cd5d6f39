; E0109 duplicate-definition: the predicate `at` is declared twice; the second
; declaration is ignored.
; Fix: delete one of them (or rename it if they mean different things).
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint)
    (at ?r - rover ?w - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

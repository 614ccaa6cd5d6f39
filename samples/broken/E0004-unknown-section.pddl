; E0004 unknown-section: `:preconditions` is not a field of an action (the
; keyword is `:precondition`); the condition that follows it is skipped.
; Fix: write `:precondition`.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :preconditions (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (road ?from ?to) (at ?r ?to))))

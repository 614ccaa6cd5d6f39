; E0106 undefined-object, domain: correct. The error is in problem.pddl.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

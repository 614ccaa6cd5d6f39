; W0207 unsupported: `(:process …)` is PDDL+ (continuous change). hipop reads
; the domain but reports this one warning and nothing else about it: it does
; not check PDDL+, and its planner and validator cannot use processes and events.
; Fix: model the recharge as a durative action (PDDL 2.1), or use a PDDL+ tool.
(define (domain rovers)
  (:requirements :typing :numeric-fluents :time)
  (:types rover)
  (:predicates (docked ?r - rover))
  (:functions (battery ?r - rover) - number)

  (:process recharge
    :parameters (?r - rover)
    :precondition (and (docked ?r) (< (battery ?r) 100))
    :effect (increase (battery ?r) (* #t 2.0))))

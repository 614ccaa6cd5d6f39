; PDDL+ with an event only: the tank overflows as soon as it is too full.
; hipop reads it but does not simulate events.
(define (domain pddl-plus)
  (:requirements :typing :fluents :time)
  (:types tank)
  (:predicates (open ?t - tank) (overflowed ?t - tank))
  (:functions (level ?t - tank))
  (:action open-valve
    :parameters (?t - tank)
    :effect (and (open ?t) (increase (level ?t) 20)))
  (:event overflow
    :parameters (?t - tank)
    :precondition (and (>= (level ?t) 10) (not (overflowed ?t)))
    :effect (overflowed ?t)))

; PDDL+ with a process only: a valve opened by an action, a tank that fills
; while it is open. hipop reads it but does not simulate processes.
(define (domain pddl-plus)
  (:requirements :typing :fluents :time)
  (:types tank)
  (:predicates (open ?t - tank))
  (:functions (level ?t - tank))
  (:action open-valve
    :parameters (?t - tank)
    :effect (open ?t))
  (:process filling
    :parameters (?t - tank)
    :precondition (open ?t)
    :effect (increase (level ?t) (* #t 1))))

; A durative action with a continuous effect (`#t`, PDDL 2.1 level 4, as in
; VAL's Tanks sample): no process, no event, but change over time that hipop
; does not simulate.
(define (domain pddl-plus)
  (:requirements :typing :fluents :durative-actions :duration-inequalities :continuous-effects)
  (:types tank)
  (:predicates (open ?t - tank))
  (:functions (level ?t - tank))
  (:action open-valve
    :parameters (?t - tank)
    :effect (open ?t))
  (:durative-action fill
    :parameters (?t - tank)
    :duration (<= ?duration 10)
    :condition (over all (open ?t))
    :effect (increase (level ?t) (* #t 2))))

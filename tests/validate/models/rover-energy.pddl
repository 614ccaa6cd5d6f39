; A rover that charges its battery in steps of 0.1 before sampling: for the
; plan-validation fixture of a numeric condition that fails by a float error
; (7.7 + 0.1 + 0.1 + 0.1 is 7.999999999999999 in floating point, not 8).
(define (domain rover-energy)
  (:requirements :typing :fluents)
  (:types rover)
  (:predicates (sampled ?r - rover))
  (:functions (energy ?r - rover))
  (:action charge
    :parameters (?r - rover)
    :precondition (and)
    :effect (and (increase (energy ?r) 0.1)))
  (:action sample
    :parameters (?r - rover)
    :precondition (>= (energy ?r) 8)
    :effect (and (sampled ?r) (decrease (energy ?r) 8))))

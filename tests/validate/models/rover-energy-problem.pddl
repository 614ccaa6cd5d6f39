; The problem of `rover-energy.pddl`: sample with a battery at 7.7.
(define (problem low-battery)
  (:domain rover-energy)
  (:objects rover0 - rover)
  (:init (= (energy rover0) 7.7))
  (:goal (sampled rover0)))

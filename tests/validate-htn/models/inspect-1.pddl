; The place opens at 5 (a timed initial literal).
(define (problem inspect-1)
  (:domain inspect)
  (:objects r1 - robot a - place)
  (:init (at r1 a) (at 5 (open a)))
  (:goal (visited a)))

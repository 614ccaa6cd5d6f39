; A correct problem of the broken domain.
(define (problem shut-a) (:domain broken)
  (:objects a - tank)
  (:init (open a))
  (:goal (not (open a))))

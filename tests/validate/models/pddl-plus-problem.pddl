; The problem of the PDDL+ domains `pddl-plus-*.pddl`: open the valve.
(define (problem open-the-valve)
  (:domain pddl-plus)
  (:objects t1 - tank)
  (:init (= (level t1) 0))
  (:goal (open t1)))

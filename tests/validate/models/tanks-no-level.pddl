; `(level a)` has no value: filling tank `a` cannot increase it.
(define (problem no-level) (:domain tanks)
  (:objects a - tank)
  (:init (open a) (= (rate a) 2) (= (spent) 0) (= (penalty) 0))
  (:goal (open a)))

; Every fluent the plan uses has a value, but the metric reads `(penalty)`, which has none.
(define (problem no-penalty) (:domain tanks)
  (:objects a - tank)
  (:init (open a) (= (rate a) 2) (= (level a) 0) (= (spent) 0))
  (:goal (>= (level a) 10))
  (:metric minimize (+ (total-time) (penalty))))

; A numeric condition `over all` on a fluent that effects change: the
; planner reports it before searching (E0501), at the condition.
(define (domain pump)
  (:requirements :durative-actions :numeric-fluents)
  (:predicates (pumped))
  (:functions (pressure))
  (:durative-action pump :parameters () :duration (= ?duration 2)
    :condition (over all (>= (pressure) 1))
    :effect (and (at end (pumped)) (at end (decrease (pressure) 1)))))

(define (problem pump-1)
  (:domain pump)
  (:init (= (pressure) 3))
  (:goal (pumped)))

; A numeric condition comparing two fluents that effects change: the
; planner reports it before searching (E0501), at the condition.
(define (domain tanks)
  (:requirements :durative-actions :numeric-fluents)
  (:predicates (poured))
  (:functions (left) (right))
  (:durative-action pour :parameters () :duration (= ?duration 1)
    :condition (at start (> (left) (right)))
    :effect (and (at end (poured)) (at end (decrease (left) 1)) (at end (increase (right) 1)))))

(define (problem tanks-1)
  (:domain tanks)
  (:init (= (left) 3) (= (right) 0))
  (:goal (poured)))

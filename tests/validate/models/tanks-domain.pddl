; A small numeric domain of hipop's own, for the plan-validation fixtures
; that need what the IPC 2002 problems never do: a fluent without a value.
(define (domain tanks)
  (:requirements :typing :fluents :durative-actions)
  (:types tank)
  (:predicates (open ?t - tank))
  (:functions (level ?t - tank) (rate ?t - tank) (spent) (penalty))
  (:durative-action fill
    :parameters (?t - tank)
    :duration (= ?duration (/ 10 (rate ?t)))
    :condition (at start (open ?t))
    :effect (and (at end (increase (level ?t) 10))
                 (at end (increase (spent) ?duration)))))

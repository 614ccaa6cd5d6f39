; Two blocks on the table, the goal a tower. Checks with no diagnostic.
(define (problem tower)
  (:domain blocks)
  (:objects a b - block)
  (:init (on a table) (on b table) (clear a) (clear b) (clear table))
  (:goal (on a b)))

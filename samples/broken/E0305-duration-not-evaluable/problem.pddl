; E0305 duration-not-evaluable: `:init` gives no `(speed rover1)`, so no move
; of `rover1` has a duration: `move` can never be applied, and the goal is out
; of reach. Fix: add `(= (speed rover1) 0.5)`.
(define (problem rover-moves-1)
  (:domain rover-moves)
  (:objects
    rover1 - rover
    base ridge crater - waypoint)
  (:init
    (at rover1 base)
    (road base ridge)
    (road ridge base)
    (road ridge crater)
    (= (distance ridge crater) 41.2)
    (= (distance base ridge) 30.98)
    (= (distance ridge base) 30.98))
  (:goal (at rover1 crater)))

; Clean counterpart of I0306 duration-undefined: every road has its
; `distance` and the rover its `speed`, so every move has a duration.
(define (problem rover-moves-1)
  (:domain rover-moves)
  (:objects
    rover1 - rover
    base ridge crater - waypoint)
  (:init
    (at rover1 base)
    (= (speed rover1) 0.5)
    (road base ridge)
    (road ridge base)
    (road ridge crater)
    (= (distance base ridge) 30.98)
    (= (distance ridge base) 30.98)
    (= (distance ridge crater) 41.2))
  (:goal (at rover1 crater)))

; Clean counterpart of W0315 invalid-duration-value: every distance and speed is
; positive, so every move has a positive duration.
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

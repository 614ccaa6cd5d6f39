; W0315 invalid-duration-value: `(distance ridge crater)` is -41.2, a sign
; typo, so the duration of `(move rover1 ridge crater)` is negative and the
; move is not applicable. Fix: `(= (distance ridge crater) 41.2)`.
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
    (= (distance ridge crater) -41.2)
    (= (distance base ridge) 30.98)
    (= (distance ridge base) 30.98))
  (:goal (at rover1 crater)))

; I0306 duration-undefined: there is a road from `ridge` to `crater`, but
; `:init` gives no `(distance ridge crater)`, so `(move rover1 ridge crater)`
; has no duration and is not applicable. Fine if that road is not meant to be
; driven; otherwise add `(= (distance ridge crater) 41.2)`.
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
    (= (distance ridge base) 30.98))
  (:goal (at rover1 ridge)))

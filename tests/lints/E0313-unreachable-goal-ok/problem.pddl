; `p2` is visible from `b`: every goal can be reached.
(define (problem survey-two)
  (:domain survey)
  (:objects r1 - robot a b - waypoint p1 p2 - poi)
  (:init (at r1 a) (visible a p1) (visible b p2))
  (:goal (and (observed p1) (observed p2)))
  (:allowed-actions move observe))

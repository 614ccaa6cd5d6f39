; E0313 unreachable-goal: `p2` is visible from no waypoint, so no allowed
; action can ever observe it: the goal `(observed p2)` is out of reach even
; ignoring deletions. Add `(visible b p2)` (or whatever makes it observable),
; or allow the action that achieves it.
(define (problem survey-two)
  (:domain survey)
  (:objects r1 - robot a b - waypoint p1 p2 - poi)
  (:init (at r1 a) (visible a p1))
  (:goal (and (observed p1) (observed p2)))
  (:allowed-actions move observe))

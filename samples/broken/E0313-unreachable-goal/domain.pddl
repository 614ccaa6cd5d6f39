; E0313 unreachable-goal: see problem.pddl.
(define (domain survey)
  (:requirements :typing :durative-actions)
  (:types robot waypoint poi)
  (:predicates (at ?r - robot ?w - waypoint) (visible ?w - waypoint ?p - poi) (observed ?p - poi))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :duration (= ?duration 5)
    :condition (at start (at ?r ?from))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to))))
  (:durative-action observe
    :parameters (?r - robot ?w - waypoint ?p - poi)
    :duration (= ?duration 2)
    :condition (and (at start (at ?r ?w)) (over all (at ?r ?w)) (at start (visible ?w ?p)))
    :effect (at end (observed ?p))))

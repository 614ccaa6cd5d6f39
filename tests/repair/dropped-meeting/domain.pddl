; Two robots that must observe a point each and meet inside a window (the
; surveillance mission's meetings, section 5.5 of the HiPOP paper).
(define (domain meeting)
  (:requirements :typing :durative-actions :timed-initial-literals)
  (:types robot waypoint poi)
  (:predicates
    (at-r ?r - robot ?w - waypoint)
    (adjacent ?from ?to - waypoint)
    (visible ?r - robot ?w - waypoint ?p - poi)
    (observed ?p - poi)
    (visible-com ?r1 ?r2 - robot ?w1 ?w2 - waypoint)
    (meeting-window ?r1 ?r2 - robot)
    (met ?r1 ?r2 - robot))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and (at start (at-r ?r ?from)) (over all (adjacent ?from ?to)))
    :effect (and (at start (not (at-r ?r ?from))) (at end (at-r ?r ?to))))
  (:durative-action observe
    :parameters (?r - robot ?w - waypoint ?p - poi)
    :agent (?r)
    :duration (= ?duration 5)
    :condition (and (at start (at-r ?r ?w)) (over all (at-r ?r ?w)) (at start (visible ?r ?w ?p)))
    :effect (at end (observed ?p)))
  (:durative-action communicate
    :parameters (?r1 ?r2 - robot ?w1 ?w2 - waypoint)
    :agent (?r1 ?r2)
    :duration (= ?duration 5)
    :condition (and
      (at start (at-r ?r1 ?w1)) (over all (at-r ?r1 ?w1))
      (at start (at-r ?r2 ?w2)) (over all (at-r ?r2 ?w2))
      (at start (visible-com ?r1 ?r2 ?w1 ?w2))
      (over all (meeting-window ?r1 ?r2)))
    :effect (at end (met ?r1 ?r2))))

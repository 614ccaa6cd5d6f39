; A patrol that lasts exactly its subtasks and the 0.01 s between them, and
; whose effect is made by its last subtask: the effect holds once that
; subtask ends, at the patrol's own end (the same happening, no 0.01 s
; after it). And only the patrol's own subtasks make its effects: the idle
; second robot is not sent on another patrol to observe p1 for the first.
(define (domain patrols)
  (:requirements :typing :durative-actions :hierarchy)
  (:types robot waypoint poi)
  (:constants a b - waypoint p1 - poi)
  (:predicates
    (at-r ?r - robot ?w - waypoint)
    (adjacent ?from ?to - waypoint)
    (visible ?w - waypoint ?p - poi)
    (observed ?p - poi))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and
      (over all (adjacent ?from ?to))
      (at start (at-r ?r ?from)))
    :effect (and
      (at start (not (at-r ?r ?from)))
      (at end (at-r ?r ?to))))
  (:durative-action observe
    :parameters (?r - robot ?w - waypoint ?p - poi)
    :agent (?r)
    :duration (= ?duration 5)
    :condition (and
      (at start (at-r ?r ?w))
      (over all (at-r ?r ?w))
      (at start (visible ?w ?p)))
    :effect (at end (observed ?p)))
  (:task patrol
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 25.02)
    :condition (at start (at-r ?r a))
    :effect (and
      (at end (observed p1))
      (at end (at-r ?r a)))
    :conflicts (and (at-r ?r ?w)))
  (:method patrol-route
    :parameters (?r - robot)
    :task (patrol ?r)
    :ordered-subtasks (and
      (t1 (move ?r a b))
      (t2 (observe ?r b p1))
      (t3 (move ?r b a)))))

(define (problem patrols-1)
  (:domain patrols)
  (:objects r1 r2 - robot)
  (:allowed-actions move patrol)
  (:htn :subtasks (and (t1 (patrol r1))))
  (:init
    (at-r r1 a) (at-r r2 a)
    (adjacent a b) (adjacent b a)
    (visible b p1))
  (:goal (and (observed p1) (at-r r1 a))))

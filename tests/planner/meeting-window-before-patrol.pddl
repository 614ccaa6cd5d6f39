; A robot must report from c inside a window (10 s to 40 s) and patrol from
; b, a patrol of 100 s that cannot overlap anything the robot's position
; serves (its conflicts). The report must come first, so the chain of moves
; to the patrol's start must leave from c, not from the robot's initial
; position: whether the report comes before or after the patrol is decided
; before any chain of moves is chosen.
(define (domain meeting)
  (:requirements :typing :durative-actions :timed-initial-literals :hierarchy)
  (:types robot waypoint poi)
  (:constants a b c d - waypoint p1 - poi)
  (:predicates
    (at-r ?r - robot ?w - waypoint)
    (adjacent ?from ?to - waypoint)
    (visible ?w - waypoint ?p - poi)
    (observed ?p - poi)
    (window-open)
    (reported ?r - robot))
  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :agent (?r)
    :duration (= ?duration 5)
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
  (:durative-action report
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and
      (at start (at-r ?r c))
      (over all (at-r ?r c))
      (at start (window-open))
      (over all (window-open))
      (at end (window-open)))
    :effect (at end (reported ?r)))
  (:task patrol
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 100)
    :condition (at start (at-r ?r b))
    :effect (at end (observed p1))
    :conflicts (and (at-r ?r ?w)))
  (:method patrol-route
    :parameters (?r - robot)
    :task (patrol ?r)
    :ordered-subtasks (and
      (t1 (move ?r b d))
      (t2 (observe ?r d p1))
      (t3 (move ?r d b)))))

(define (problem meeting-1)
  (:domain meeting)
  (:objects r1 - robot)
  (:allowed-actions move report patrol)
  (:init
    (at-r r1 a)
    (adjacent a b) (adjacent b a) (adjacent a c) (adjacent c a)
    (adjacent b c) (adjacent c b) (adjacent b d) (adjacent d b)
    (visible d p1)
    (at 10 (window-open))
    (at 40 (not (window-open))))
  (:goal (and (observed p1) (reported r1))))

; A patrol whose duration is exactly its moves and observation: with the
; 0.01 s that separates its ordered subtasks, its only method cannot fit in
; it, so the `:htn` asking for it has no plan (E0502), and the abstract flaw
; says by how much (I0506).
(define (domain patrols)
  (:requirements :typing :durative-actions :hierarchy)
  (:types robot waypoint poi)
  (:constants a b c d - waypoint p1 p2 - poi)
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
  (:task patrol-1
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 25)
    :condition (at start (at-r ?r a))
    :effect (at end (observed p1))
    :conflicts (and (at-r ?r ?w)))
  (:method patrol-1-route
    :parameters (?r - robot)
    :task (patrol-1 ?r)
    :ordered-subtasks (and
      (t1 (move ?r a b))
      (t2 (observe ?r b p1))
      (t3 (move ?r b a))))
  (:task patrol-2
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 25)
    :condition (at start (at-r ?r c))
    :effect (at end (observed p2))
    :conflicts (and (at-r ?r ?w)))
  (:method patrol-2-route
    :parameters (?r - robot)
    :task (patrol-2 ?r)
    :ordered-subtasks (and
      (t1 (move ?r c d))
      (t2 (observe ?r d p2))
      (t3 (move ?r d c)))))

(define (problem patrols-1)
  (:domain patrols)
  (:objects r1 - robot)
  (:allowed-actions move patrol-1 patrol-2)
  (:htn :subtasks (and (t1 (patrol-1 r1))))
  (:init
    (at-r r1 a)
    (adjacent a b) (adjacent b a) (adjacent a c) (adjacent c a) (adjacent c d) (adjacent d c)
    (visible b p1) (visible d p2))
  (:goal (and (observed p1) (observed p2))))

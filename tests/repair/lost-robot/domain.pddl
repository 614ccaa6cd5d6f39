; A robot out of service during a mission (section 5.5 of the HiPOP paper),
; small enough to read: three robots, one patrol observes two points of
; interest from b and c.
(define (domain lost-robot)
  (:requirements :typing :durative-actions :timed-initial-literals :hierarchy)
  (:types robot waypoint poi)
  (:constants b c - waypoint p1 p2 - poi)
  (:predicates
    (at-r ?r - robot ?w - waypoint)
    (adjacent ?from ?to - waypoint)
    (visible ?r - robot ?w - waypoint ?p - poi)   ; ?r's sensor sees ?p from ?w
    (observed ?p - poi))

  (:durative-action move
    :parameters (?r - robot ?from ?to - waypoint)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and
      (at start (at-r ?r ?from))
      (over all (adjacent ?from ?to)))
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
      (at start (visible ?r ?w ?p)))
    :effect (at end (observed ?p)))

  ; From b: observe p1, go to c, observe p2, come back to b.
  (:task patrol
    :parameters (?r - robot)
    :agent (?r)
    :duration (= ?duration 40)
    :condition (at start (at-r ?r b))
    :effect (and (at end (observed p1)) (at end (observed p2)))
    :conflicts (and (at-r ?r ?w)))
  (:method patrol-b-c
    :parameters (?r - robot)
    :task (patrol ?r)
    :ordered-subtasks (and
      (observe ?r b p1)
      (move ?r b c)
      (observe ?r c p2)
      (move ?r c b))))

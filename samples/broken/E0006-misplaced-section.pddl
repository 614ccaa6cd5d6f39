; E0006 misplaced-section: `(:objects …)` is a problem section; in a domain,
; names shared by every problem are `(:constants …)`. The objects declared here
; are ignored by the domain.
; Fix: rename the section to `(:constants …)`, or move it to the problem.
(define (domain rovers)
  (:requirements :typing)
  (:types rover waypoint)
  (:objects base - waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))

  (:action move
    :parameters (?r - rover ?from ?to - waypoint)
    :precondition (and (at ?r ?from) (road ?from ?to))
    :effect (and (not (at ?r ?from)) (at ?r ?to))))

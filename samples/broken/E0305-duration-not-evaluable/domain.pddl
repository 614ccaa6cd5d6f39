; E0305 duration-not-evaluable, domain: correct. The duration of `move` reads
; `(distance ?from ?to)` and `(speed ?r)`, which every problem must define for
; the moves it allows; problem.pddl does not (the error is shown here, on the
; fluent that has no value).
(define (domain rover-moves)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types rover waypoint)
  (:predicates
    (at ?r - rover ?w - waypoint)
    (road ?from ?to - waypoint))
  (:functions
    (distance ?from ?to - waypoint)
    (speed ?r - rover))

  (:durative-action move
    :parameters (?r - rover ?from ?to - waypoint)
    :duration (= ?duration (/ (distance ?from ?to) (speed ?r)))
    :condition (and (at start (at ?r ?from)) (over all (road ?from ?to)))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to)))))

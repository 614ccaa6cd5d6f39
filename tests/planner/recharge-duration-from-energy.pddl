; A rover with energy for one move: it recharges in the sun where it starts,
; for as long as its energy left says ((20 - 10) / 2 = 5), before two moves.
(define (domain rover-energy)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types rover waypoint)
  (:predicates (at ?r - rover ?w - waypoint) (in_sun ?w - waypoint) (path ?a ?b - waypoint))
  (:functions (energy ?r - rover) (recharge-rate ?r - rover))
  (:durative-action navigate
    :parameters (?r - rover ?a ?b - waypoint)
    :duration (= ?duration 5)
    :condition (and (at start (at ?r ?a)) (over all (path ?a ?b)) (at start (>= (energy ?r) 8)))
    :effect (and (at start (decrease (energy ?r) 8)) (at start (not (at ?r ?a))) (at end (at ?r ?b))))
  (:durative-action recharge
    :parameters (?r - rover ?w - waypoint)
    :duration (= ?duration (/ (- 20 (energy ?r)) (recharge-rate ?r)))
    :condition (and (at start (at ?r ?w)) (over all (at ?r ?w)) (at start (in_sun ?w))
                    (at start (<= (energy ?r) 20)))
    :effect (at end (increase (energy ?r) (* ?duration (recharge-rate ?r))))))

(define (problem two-moves)
  (:domain rover-energy)
  (:objects rover0 - rover w0 w1 w2 - waypoint)
  (:init (at rover0 w0) (in_sun w0) (path w0 w1) (path w1 w2)
    (= (energy rover0) 10) (= (recharge-rate rover0) 2))
  (:goal (at rover0 w2)))

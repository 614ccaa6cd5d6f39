; Durations that are no multiple of a millisecond: a constant (0.5146), a
; fluent divided by another (0.5146 / 3, 131.5 / 3), as IPC 2002
; satellite-time's slews. The plan must write them exactly: rounded to
; three decimals, 0.515 misses 0.5146 by more than a tolerance of 0.0001,
; and the plan is invalid there. Its times are off the grid too, and a
; timed literal at 140.0007 closes the window every shot needs.
(define (domain slews)
  (:requirements :typing :durative-actions :numeric-fluents :timed-initial-literals)
  (:types sat dir)
  (:predicates (pointing ?s - sat ?d - dir) (imaged ?d - dir) (window))
  (:functions (slew ?a ?b - dir) (speed ?s - sat))
  (:durative-action turn
    :parameters (?s - sat ?from ?to - dir)
    :duration (= ?duration (/ (slew ?from ?to) (speed ?s)))
    :condition (at start (pointing ?s ?from))
    :effect (and (at start (not (pointing ?s ?from))) (at end (pointing ?s ?to))))
  (:durative-action shoot
    :parameters (?s - sat ?d - dir)
    :duration (= ?duration 0.5146)
    :condition (and (at start (pointing ?s ?d)) (over all (pointing ?s ?d)) (over all (window)))
    :effect (at end (imaged ?d))))

(define (problem slews-1)
  (:domain slews)
  (:objects s1 s2 - sat d0 d1 d2 d3 - dir)
  (:init (pointing s1 d0) (pointing s2 d0) (window) (at 140.0007 (not (window)))
    (= (speed s1) 3) (= (speed s2) 1)
    (= (slew d0 d1) 0.5146) (= (slew d1 d2) 131.5) (= (slew d0 d2) 400) (= (slew d1 d3) 1.23456789)
    (= (slew d0 d3) 400) (= (slew d2 d3) 400) (= (slew d3 d2) 400) (= (slew d2 d1) 400)
    (= (slew d1 d0) 400) (= (slew d2 d0) 400) (= (slew d3 d0) 400) (= (slew d3 d1) 400)
    (= (slew d0 d0) 400) (= (slew d1 d1) 400) (= (slew d2 d2) 400) (= (slew d3 d3) 400))
  (:goal (and (imaged d1) (imaged d2) (imaged d3))))

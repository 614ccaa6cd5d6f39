; A plane with fuel for one leg at a time: it must refuel at city1 before
; the second flight (a numeric condition at the flight's start, a refuel
; whose duration reads the fuel left).
(define (domain zeno-legs)
  (:requirements :typing :durative-actions :numeric-fluents)
  (:types aircraft city)
  (:predicates (at ?a - aircraft ?c - city))
  (:functions (fuel ?a - aircraft) (capacity ?a - aircraft) (refuel-rate ?a - aircraft)
    (distance ?c1 ?c2 - city) (speed ?a - aircraft) (burn ?a - aircraft) (total-fuel-used))
  (:durative-action fly
    :parameters (?a - aircraft ?c1 ?c2 - city)
    :duration (= ?duration (/ (distance ?c1 ?c2) (speed ?a)))
    :condition (and (at start (at ?a ?c1))
                    (at start (>= (fuel ?a) (* (distance ?c1 ?c2) (burn ?a)))))
    :effect (and (at start (not (at ?a ?c1)))
                 (at end (at ?a ?c2))
                 (at end (increase (total-fuel-used) (* (distance ?c1 ?c2) (burn ?a))))
                 (at end (decrease (fuel ?a) (* (distance ?c1 ?c2) (burn ?a))))))
  (:durative-action refuel
    :parameters (?a - aircraft ?c - city)
    :duration (= ?duration (/ (- (capacity ?a) (fuel ?a)) (refuel-rate ?a)))
    :condition (and (at start (> (capacity ?a) (fuel ?a)))
                    (over all (at ?a ?c)))
    :effect (at end (assign (fuel ?a) (capacity ?a)))))

(define (problem two-legs)
  (:domain zeno-legs)
  (:objects plane1 - aircraft city0 city1 city2 - city)
  (:init (at plane1 city0)
    (= (fuel plane1) 10) (= (capacity plane1) 10) (= (refuel-rate plane1) 4)
    (= (speed plane1) 2) (= (burn plane1) 1) (= (total-fuel-used) 0)
    (= (distance city0 city1) 6) (= (distance city1 city0) 6)
    (= (distance city1 city2) 6) (= (distance city2 city1) 6))
  (:goal (at plane1 city2)))

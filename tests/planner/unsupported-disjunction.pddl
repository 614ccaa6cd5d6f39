; A precondition with `or`: the planner reports it before searching (E0501).
(define (domain lamps)
  (:requirements :strips :disjunctive-preconditions)
  (:predicates (on ?l) (powered))
  (:action switch-on
    :parameters (?l)
    :precondition (or (powered) (on ?l))
    :effect (on ?l)))

(define (problem lamps-1)
  (:domain lamps)
  (:objects lamp1)
  (:init (powered))
  (:goal (on lamp1)))

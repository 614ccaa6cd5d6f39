; An `over all` effect (not PDDL 2.1: a continuous change): the planner
; reports it before searching (E0501), as the validator refuses it in a
; plan, instead of treating it as an `at end` effect.
(define (domain heater)
  (:requirements :strips :durative-actions)
  (:predicates (warm))
  (:durative-action heat
    :parameters ()
    :duration (= ?duration 3)
    :condition (and)
    :effect (and (over all (warm)))))

(define (problem heater-1)
  (:domain heater)
  (:init)
  (:goal (warm)))

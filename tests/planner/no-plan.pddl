; Two lamps share one switch that turns one lamp off when it turns the other
; on: both can never be on together (E0502, with the threats of the best partial
; plan, I0505).
(define (domain toggles)
  (:requirements :strips)
  (:predicates (on ?l))
  (:constants lamp1 lamp2)
  (:action light-1
    :parameters ()
    :effect (and (on lamp1) (not (on lamp2))))
  (:action light-2
    :parameters ()
    :effect (and (on lamp2) (not (on lamp1)))))

(define (problem toggles-1)
  (:domain toggles)
  (:init)
  (:goal (and (on lamp1) (on lamp2))))

; W0205 domain-mismatch: this problem is for the domain `rovers`, but the only
; domain beside it (domain.pddl) is `rover-mission`. hipop checks the problem
; against that domain anyway, and warns.
; Fix: write `(:domain rover-mission)` (hipop offers the edit), or pass the
; right domain file.
(define (problem rovers-1)
  (:domain rovers)
  (:objects
    rover1 - rover
    base ridge - waypoint)
  (:init
    (at rover1 base)
    (road base ridge))
  (:goal (at rover1 ridge)))

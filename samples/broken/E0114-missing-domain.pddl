; E0114 missing-domain: this problem is for the domain `rover-patrol`, but no
; file given to hipop defines it (it is checked alone here), so the names of
; the problem cannot be checked.
; Fix: pass the domain file too (`hipop check domain.pddl problem.pddl`, or the
; folder), or correct the name in `(:domain …)`.
(define (problem rover-patrol-1)
  (:domain rover-patrol)
  (:objects
    rover1 - rover
    base ridge - waypoint)
  (:init
    (at rover1 base)
    (road base ridge))
  (:goal (at rover1 ridge)))

; E0106 undefined-object: the initial state has a road to `crater`, but
; `(:objects …)` does not declare `crater` (nor does the domain as a constant).
; Fix: declare it, e.g. `base ridge crater - waypoint`, or correct the name.
(define (problem rovers-1)
  (:domain rovers)
  (:objects
    rover1 - rover
    base ridge - waypoint)
  (:init
    (at rover1 base)
    (road base ridge)
    (road ridge crater))
  (:goal (at rover1 ridge)))

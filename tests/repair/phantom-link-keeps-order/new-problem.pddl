; The event: the photograph of z1 is no longer needed.
(define (problem site-1)
  (:domain site)
  (:objects c1 - camera z1 z2 z3 - zone)
  (:init (quiet))
  (:goal (and (drilled z2) (photographed z3))))

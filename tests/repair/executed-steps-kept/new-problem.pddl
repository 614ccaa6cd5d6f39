; The event, at time 3: no photograph is needed any more, and a second
; camera, c2, must be set up. The camera c1 was set up already.
(define (problem site-1)
  (:domain site)
  (:objects c1 c2 - camera z1 z2 z3 - zone)
  (:init (quiet))
  (:goal (and (drilled z2) (ready c2))))

; The mission: robots r1 at a, r2 one move further (d), r3 two (e), on the
; line e - d - a - b - c; p2 is to be observed (a patrol from b does it).
(define (problem lost-robot-1)
  (:domain lost-robot)
  (:objects r1 r2 r3 - robot a d e - waypoint)
  (:allowed-actions move patrol)
  (:init
    (at-r r1 a) (at-r r2 d) (at-r r3 e)
    (adjacent e d) (adjacent d e) (adjacent d a) (adjacent a d)
    (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b)
    (visible r1 b p1) (visible r1 c p2)
    (visible r2 b p1) (visible r2 c p2)
    (visible r3 b p1) (visible r3 c p2))
  (:goal (observed p2)))

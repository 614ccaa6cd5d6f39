; The mission of problem.pddl after r1's sensor fails at 5 s: from then on,
; r1 no longer sees anything (its visible facts end at 5 s).
(define (problem lost-robot-1-r1-out)
  (:domain lost-robot)
  (:objects r1 r2 r3 - robot a d e - waypoint)
  (:allowed-actions move patrol)
  (:init
    (at-r r1 a) (at-r r2 d) (at-r r3 e)
    (adjacent e d) (adjacent d e) (adjacent d a) (adjacent a d)
    (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b)
    (visible r1 b p1) (visible r1 c p2)
    (visible r2 b p1) (visible r2 c p2)
    (visible r3 b p1) (visible r3 c p2)
    (at 5 (not (visible r1 b p1))) (at 5 (not (visible r1 c p2))))
  (:goal (observed p2)))

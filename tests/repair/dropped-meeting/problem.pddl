; r1 and r2 observe p1 and p2, and meet at b (r1) and c (r2) between 20 and 60.
; The old plan of the repair fixtures in this folder.
(define (problem meeting-1)
  (:domain meeting)
  (:objects r1 r2 - robot a b c d - waypoint p1 p2 - poi)
  (:init
    (at-r r1 a) (at-r r2 d)
    (adjacent a b) (adjacent b a) (adjacent c d) (adjacent d c)
    (visible r1 a p1) (visible r2 d p2)
    (visible-com r1 r2 b c)
    (at 20 (meeting-window r1 r2))
    (at 60 (not (meeting-window r1 r2))))
  (:goal (and (observed p1) (observed p2) (met r1 r2))))

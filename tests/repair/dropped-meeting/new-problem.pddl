; After the event: the meeting's window closes at 24, too early for a
; communication (5 s) to fit in it; r2 is out of communication. No plan keeps
; the meeting: the repair drops it and keeps the observations.
(define (problem meeting-1-after)
  (:domain meeting)
  (:objects r1 r2 - robot a b c d - waypoint p1 p2 - poi)
  (:init
    (at-r r1 a) (at-r r2 d)
    (adjacent a b) (adjacent b a) (adjacent c d) (adjacent d c)
    (visible r1 a p1) (visible r2 d p2)
    (visible-com r1 r2 b c)
    (at 20 (meeting-window r1 r2))
    (at 24 (not (meeting-window r1 r2))))
  (:goal (and (observed p1) (observed p2) (met r1 r2))))

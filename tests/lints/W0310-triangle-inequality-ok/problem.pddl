; A 3-4-5 triangle: no direct move is slower than a detour. The inequality as
; the paper prints it, dur(f->g) + dur(g->h) <= dur(f->h), would flag every
; pair here (3 + 4 > 5): hipop checks the one its text means.
(define (problem reach-c)
  (:domain rovers-geo)
  (:objects r1 - robot a b c - waypoint)
  (:init
    (at r1 a)
    (= (distance a b) 3)
    (= (distance b a) 3)
    (= (distance b c) 4)
    (= (distance c b) 4)
    (= (distance a c) 5)
    (= (distance c a) 5))
  (:goal (at r1 c)))

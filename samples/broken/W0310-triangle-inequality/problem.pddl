; W0310 triangle-inequality: moving from `a` to `c` directly takes 10, but
; through `b` it takes 3 + 4 = 7. The planner uses move durations as lower
; bounds of the time between two positions, which is only sound when a direct
; move is never slower than a detour. The paper prints the inequality the
; other way round (3 + 4 <= 10 holds here); its text is what counts. Fix the
; distance (here 5) or silence with `; hipop-allow: W0310`.
(define (problem reach-c)
  (:domain rovers-geo)
  (:objects r1 - robot a b c - waypoint)
  (:init
    (at r1 a)
    (= (distance a b) 3)
    (= (distance b a) 3)
    (= (distance b c) 4)
    (= (distance c b) 4)
    (= (distance a c) 10)
    (= (distance c a) 10))
  (:goal (at r1 c)))

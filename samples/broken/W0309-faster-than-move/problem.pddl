; W0309 faster-than-move: see the domain.
(define (problem reach-c)
  (:domain rovers-geo)
  (:objects r1 - robot a b c - waypoint)
  (:init
    (at r1 a)
    (charged r1)
    (= (distance a b) 3)
    (= (distance b a) 3)
    (= (distance b c) 4)
    (= (distance c b) 4)
    (= (distance a c) 5)
    (= (distance c a) 5))
  (:goal (at r1 c)))

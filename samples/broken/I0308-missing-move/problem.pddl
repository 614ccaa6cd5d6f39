; I0308 missing-move: see the domain.
(define (problem reach-c)
  (:domain rovers-geo)
  (:objects r1 - robot a b c - waypoint)
  (:init
    (at r1 a)
    (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b)
    (= (distance a b) 3)
    (= (distance b a) 3)
    (= (distance b c) 4)
    (= (distance c b) 4))
  (:goal (at r1 c)))

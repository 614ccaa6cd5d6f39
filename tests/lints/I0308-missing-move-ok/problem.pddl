; Every two waypoints are adjacent: a move exists between any two positions.
(define (problem reach-c)
  (:domain rovers-geo)
  (:objects r1 - robot a b c - waypoint)
  (:init
    (at r1 a)
    (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b) (adjacent a c) (adjacent c a)
    (= (distance a b) 3)
    (= (distance b a) 3)
    (= (distance b c) 4)
    (= (distance c b) 4)
    (= (distance a c) 5)
    (= (distance c a) 5))
  (:goal (at r1 c)))

; The crate found at c, not at b where it was reported; r1 (a lifter) at a, r2 (a hauler) at d; the
; depot at d, on the line a - b - c - d; a road c -> d only.
(define (problem relay-1-moved)
  (:domain relay)
  (:objects r1 r2 - robot k - crate a b c d - place)
  (:allowed-actions move lift haul drop)
  (:init
    (at-r r1 a) (at-r r2 d) (at-c k c) (reported k c)
    (lifter r1) (hauler r2) (depot d)
    (adjacent a b) (adjacent b a) (adjacent b c) (adjacent c b) (adjacent c d) (adjacent d c)
    (road c d))
  (:goal (delivered k)))

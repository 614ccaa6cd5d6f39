; The robot is in two rooms at once: `at-robby *` is not a position family
; (property 1), and the note, shown because `move` is a move action, names
; the family, not an empty key.
(define (problem twice)
  (:domain gripper-one)
  (:objects rooma roomb - room)
  (:init (at-robby rooma) (at-robby roomb))
  (:goal (at-robby roomb)))

; Gripper's robot: `at-robby *` is a candidate position family of one
; argument (the robot is not named), and `move` is a move action of it.
(define (domain gripper-one)
  (:requirements :typing)
  (:types room)
  (:predicates (at-robby ?r - room))
  (:action move
    :parameters (?from ?to - room)
    :precondition (at-robby ?from)
    :effect (and (at-robby ?to) (not (at-robby ?from)))))

; Towers of blocks, one hand: ten blocks from three towers to others.
; The relaxed plan's helpful actions lead back to states already met: the
; enforced hill-climbing runs out of states after two expansions, and the
; greedy best-first search from the start finds the sequence.
(define (domain towers)
  (:requirements :typing :durative-actions)
  (:types block)
  (:predicates (on ?x ?y - block) (ontable ?x - block) (clear ?x - block) (holding ?x - block) (handempty))
  (:durative-action pick-up
    :parameters (?x - block)
    :duration (= ?duration 1)
    :condition (and (at start (clear ?x)) (at start (ontable ?x)) (at start (handempty)))
    :effect (and (at start (not (ontable ?x))) (at start (not (clear ?x))) (at start (not (handempty)))
                 (at end (holding ?x))))
  (:durative-action put-down
    :parameters (?x - block)
    :duration (= ?duration 1)
    :condition (at start (holding ?x))
    :effect (and (at start (not (holding ?x))) (at end (clear ?x)) (at end (handempty)) (at end (ontable ?x))))
  (:durative-action stack
    :parameters (?x ?y - block)
    :duration (= ?duration 1)
    :condition (and (at start (holding ?x)) (at start (clear ?y)))
    :effect (and (at start (not (holding ?x))) (at start (not (clear ?y)))
                 (at end (clear ?x)) (at end (handempty)) (at end (on ?x ?y))))
  (:durative-action unstack
    :parameters (?x ?y - block)
    :duration (= ?duration 1)
    :condition (and (at start (on ?x ?y)) (at start (clear ?x)) (at start (handempty)))
    :effect (and (at start (not (on ?x ?y))) (at start (not (clear ?x))) (at start (not (handempty)))
                 (at end (holding ?x)) (at end (clear ?y)))))
(define (problem towers-10-2) (:domain towers)
  (:objects b1 b2 b3 b4 b5 b6 b7 b8 b9 b10 - block)
  (:init (handempty) (ontable b6) (clear b1) (on b10 b6) (on b4 b10) (on b5 b4) (on b7 b5) (on b8 b7) (on b3 b8) (on b9 b3) (on b2 b9) (on b1 b2))
  (:goal (and (on b2 b10) (on b8 b2) (on b9 b8) (on b5 b9) (on b4 b5) (on b6 b4) (on b7 b6) (on b3 b7))))

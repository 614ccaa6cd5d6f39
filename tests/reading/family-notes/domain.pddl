; Blocks moved from one block to another: `on ? *` looks like a position
; (the move deletes `(on ?b ?from)` and adds `(on ?b ?to)`), but it is not a
; position family, and nobody meant one: `move` needs `clear` blocks, so it
; is not a move action, and the domain uses no HiPOP extension. hipop says
; nothing about it (I0307 would be noise on every problem); hovering `on`
; still says why it is not a family.
(define (domain blocks)
  (:requirements :typing)
  (:types block)
  (:constants table - block)
  (:predicates (on ?b ?on - block) (clear ?b - block))
  (:action move
    :parameters (?b ?from ?to - block)
    :precondition (and (on ?b ?from) (clear ?b) (clear ?to))
    :effect (and (not (on ?b ?from)) (on ?b ?to) (clear ?from) (not (clear ?to)))))

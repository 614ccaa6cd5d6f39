; E0115 negative-duration: the duration of `charge` is -2.5, a sign typo: no
; duration is negative, so `charge` can never be applied.
; Fix: `(= ?duration 2.5)`.
(define (domain rover-charge)
  (:requirements :typing :durative-actions)
  (:types rover)
  (:predicates (docked ?r - rover) (charged ?r - rover))
  (:durative-action charge
    :parameters (?r - rover)
    :duration (= ?duration -2.5)
    :condition (over all (docked ?r))
    :effect (at end (charged ?r))))

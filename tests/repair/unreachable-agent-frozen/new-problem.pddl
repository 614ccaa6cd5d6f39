; The event: the inspection of w2 is no longer needed, two new wells, w3
; and w4, must be inspected, and r1 is out of communication
; (`--unreachable r1`): it goes on with its plan, which the repair cannot
; change, nor give it anything new to do.
(define (problem wells-1)
  (:domain wells)
  (:objects r1 r2 - robot p1 - probe w1 w2 w3 w4 - well)
  (:init (carries r1 p1))
  (:goal (and (inspected w1) (inspected w3) (inspected w4)))
  (:allowed-actions inspect))

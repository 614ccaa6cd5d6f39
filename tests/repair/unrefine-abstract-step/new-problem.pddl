; The event: the probe p1 is lost. The inspection of w2 by r1 used it: the
; method is gone, r1 inspects w2 by eye.
(define (problem wells-1)
  (:domain wells)
  (:objects r1 r2 - robot w1 w2 - well)
  (:init)
  (:goal (and (inspected w1) (inspected w2)))
  (:allowed-actions inspect))

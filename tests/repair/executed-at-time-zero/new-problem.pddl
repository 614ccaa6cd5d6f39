; The event, at time 1: the kit k3 is lost. The other kit, k1, fits m1
; too, but the calibration of m2, under way, has used it up.
(define (problem lab-2)
  (:domain lab)
  (:objects m1 m2 - machine k1 - kit s1 s2 - sample)
  (:init (fits k1 m1) (fits k1 m2) (unused k1)
         (suits s1 m1) (suits s1 m2) (suits s2 m2) (have s1) (have s2))
  (:goal (and (analyzed s1) (analyzed s2))))

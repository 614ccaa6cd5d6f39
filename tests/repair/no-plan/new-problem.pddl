; The event: the kit k3 is lost. Each sample suits one machine only, and
; the one kit left, k1, can calibrate one of them: even a new plan cannot
; analyse both.
(define (problem lab-4)
  (:domain lab)
  (:objects m1 m2 - machine k1 - kit s1 s2 - sample)
  (:init (fits k1 m1) (fits k1 m2) (unused k1)
         (suits s1 m1) (suits s2 m2) (have s1) (have s2))
  (:goal (and (analyzed s1) (analyzed s2))))

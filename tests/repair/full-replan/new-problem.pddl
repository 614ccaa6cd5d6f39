; The event: the kit k3 is lost. The sample s1 suits m1 only, whose only
; kit left, k1, the calibration of m2 uses up: no repair of the old plan
; works, only a new plan that calibrates m1 with k1 and analyses s1 and s2
; there. The machine m3 is not concerned.
(define (problem lab-3)
  (:domain lab)
  (:objects m1 m2 m3 - machine k1 k4 - kit s1 s2 s3 - sample)
  (:init (fits k1 m1) (fits k1 m2) (fits k4 m3) (unused k1) (unused k4)
         (suits s1 m1) (suits s2 m1) (suits s2 m2) (suits s3 m3) (have s1) (have s2) (have s3))
  (:goal (and (analyzed s1) (analyzed s2) (analyzed s3))))

; The event: the kit k1 is lost (the object is gone, with its facts).
(define (problem lab-1)
  (:domain lab)
  (:objects m1 m2 - machine k2 - kit s1 s2 - sample)
  (:init (fits k2 m2) (unused k2)
         (suits s1 m1) (suits s1 m2) (suits s2 m2) (have s1) (have s2))
  (:goal (and (analyzed s1) (analyzed s2))))

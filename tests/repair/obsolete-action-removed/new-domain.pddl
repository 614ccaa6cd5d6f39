; The laboratory after the event: the calibration kits are withdrawn, the
; action `calibrate` is gone from the domain; a machine can test itself
; instead, which takes longer.
(define (domain lab)
  (:requirements :strips :typing :durative-actions)
  (:types machine kit sample)
  (:predicates (fits ?k - kit ?m - machine) (unused ?k - kit) (calibrated ?m - machine)
               (suits ?s - sample ?m - machine) (have ?s - sample) (analyzed ?s - sample))
  (:durative-action self-test
    :parameters (?m - machine)
    :duration (= ?duration 6)
    :effect (at end (calibrated ?m)))
  (:durative-action analyze
    :parameters (?m - machine ?s - sample)
    :duration (= ?duration 5)
    :condition (and (at start (calibrated ?m)) (at start (have ?s)) (over all (suits ?s ?m)))
    :effect (at end (analyzed ?s))))

; A laboratory: a machine is calibrated with a kit that fits it (one use
; per kit), then analyses the samples that suit it.
(define (domain lab)
  (:requirements :strips :typing :durative-actions)
  (:types machine kit sample)
  (:predicates (fits ?k - kit ?m - machine) (unused ?k - kit) (calibrated ?m - machine)
               (suits ?s - sample ?m - machine) (have ?s - sample) (analyzed ?s - sample))
  ; A kit is used up by one calibration.
  (:durative-action calibrate
    :parameters (?m - machine ?k - kit)
    :duration (= ?duration 3)
    :condition (and (at start (fits ?k ?m)) (at start (unused ?k)))
    :effect (and (at start (not (unused ?k))) (at end (calibrated ?m))))
  (:durative-action analyze
    :parameters (?m - machine ?s - sample)
    :duration (= ?duration 5)
    :condition (and (at start (calibrated ?m)) (at start (have ?s)) (over all (suits ?s ?m)))
    :effect (at end (analyzed ?s))))

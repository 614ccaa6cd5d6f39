; A building site: a camera is set up, then takes photographs, which need
; quiet all along; drilling is noisy while it lasts.
(define (domain site)
  (:requirements :strips :typing :durative-actions)
  (:types camera zone)
  (:predicates (ready ?c - camera) (photographed ?z - zone) (quiet) (drilled ?z - zone))
  (:durative-action set-up
    :parameters (?c - camera)
    :duration (= ?duration 2)
    :effect (at end (ready ?c)))
  (:durative-action photograph
    :parameters (?c - camera ?z - zone)
    :duration (= ?duration 3)
    :condition (and (at start (ready ?c)) (over all (quiet)))
    :effect (at end (photographed ?z)))
  (:durative-action drill
    :parameters (?z - zone)
    :duration (= ?duration 4)
    :condition (at start (quiet))
    :effect (and (at start (not (quiet))) (at end (quiet)) (at end (drilled ?z)))))

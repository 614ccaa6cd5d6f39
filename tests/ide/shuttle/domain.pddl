; One robot that drives between places, and honks.
(define (domain shuttle)
  (:requirements :strips :typing :durative-actions)
  (:types robot place)
  (:constants depot - place)
  (:predicates (at ?r - robot ?p - place) (honked ?r - robot))
  (:durative-action drive
    :parameters (?r - robot ?from ?to - place)
    :duration (= ?duration 5)
    :condition (at start (at ?r ?from))
    :effect (and (at start (not (at ?r ?from))) (at end (at ?r ?to))))
  (:action honk
    :parameters (?r - robot)
    :effect (honked ?r)))

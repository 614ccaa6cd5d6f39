; A relay of two robots (the survivors-repair pattern of the HiPOP paper's
; section 5.2, small enough to read): r1 lifts a crate where it was reported
; and sets it down next door; r2 hauls it along one-way roads to the depot.
(define (domain relay)
  (:requirements :typing :durative-actions)
  (:types robot crate place)
  (:predicates
    (at-r ?r - robot ?p - place)
    (at-c ?c - crate ?p - place)
    (adjacent ?from ?to - place)
    (road ?from ?to - place)          ; one-way, for hauling
    (reported ?c - crate ?p - place)  ; where the crate was reported
    (lifter ?r - robot)
    (hauler ?r - robot)
    (depot ?p - place)
    (held ?c - crate)                 ; on a pallet: it can be hauled
    (delivered ?c - crate))

  (:durative-action move
    :parameters (?r - robot ?from ?to - place)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and (at start (at-r ?r ?from)) (over all (adjacent ?from ?to)))
    :effect (and (at start (not (at-r ?r ?from))) (at end (at-r ?r ?to))))

  ; Lifts the crate where it was reported onto a pallet, next door.
  (:durative-action lift
    :parameters (?r - robot ?c - crate ?from ?to - place)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and
      (over all (lifter ?r)) (over all (adjacent ?from ?to))
      (at start (reported ?c ?from))
      (at start (at-r ?r ?from)) (at start (at-c ?c ?from)))
    :effect (and
      (at start (not (at-r ?r ?from))) (at start (not (at-c ?c ?from)))
      (at end (at-r ?r ?to)) (at end (at-c ?c ?to)) (at end (held ?c))))

  (:durative-action haul
    :parameters (?r - robot ?c - crate ?from ?to - place)
    :agent (?r)
    :duration (= ?duration 10)
    :condition (and
      (over all (hauler ?r)) (over all (road ?from ?to))
      (at start (held ?c))
      (at start (at-r ?r ?from)) (at start (at-c ?c ?from)))
    :effect (and
      (at start (not (at-r ?r ?from))) (at start (not (at-c ?c ?from)))
      (at end (at-r ?r ?to)) (at end (at-c ?c ?to))))

  (:durative-action drop
    :parameters (?r - robot ?c - crate ?p - place)
    :agent (?r)
    :duration (= ?duration 5)
    :condition (and
      (over all (depot ?p)) (at start (held ?c))
      (at start (at-r ?r ?p)) (at start (at-c ?c ?p)))
    :effect (at end (delivered ?c))))

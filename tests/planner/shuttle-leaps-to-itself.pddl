; Shuttles carry riders between towns; a hop uses one charge level and a
; leap two, recharging raises the level by one. Charge levels are objects
; chained by `below` (a ZenoTravel-like domain written for this test). The
; shuttle must fetch r1 from t2 to t1 and end at t2.
;
; A greedy descent takes the cheapest child first. Once no step already in
; the plan can put the shuttle back at a town, a new `leap` from that town
; to itself is the cheapest supporter (it needs the shuttle there, which
; the initial state "gives" for free in the estimate), and its own
; condition is supported the same way: unbounded, the descent from the
; plan at 1,024 expansions went hundreds of steps down that chain, each
; expansion slower than the last (hundreds of threats). A descent now goes
; no further than twice the remaining effort of the plan it starts from.
(define (domain shuttles)
  (:requirements :durative-actions :typing)
  (:types shuttle rider town level - object)
  (:predicates (at ?x - (either rider shuttle) ?t - town)
               (aboard ?r - rider ?s - shuttle)
               (charge ?s - shuttle ?l - level)
               (below ?l1 ?l2 - level))
  (:durative-action embark
    :parameters (?r - rider ?s - shuttle ?t - town)
    :duration (= ?duration 10)
    :condition (and (at start (at ?r ?t)) (over all (at ?s ?t)))
    :effect (and (at start (not (at ?r ?t))) (at end (aboard ?r ?s))))
  (:durative-action disembark
    :parameters (?r - rider ?s - shuttle ?t - town)
    :duration (= ?duration 15)
    :condition (and (at start (aboard ?r ?s)) (over all (at ?s ?t)))
    :effect (and (at start (not (aboard ?r ?s))) (at end (at ?r ?t))))
  (:durative-action hop
    :parameters (?s - shuttle ?from ?to - town ?l1 ?l2 - level)
    :duration (= ?duration 90)
    :condition (and (at start (at ?s ?from)) (at start (charge ?s ?l1)) (at start (below ?l2 ?l1)))
    :effect (and (at start (not (at ?s ?from))) (at end (at ?s ?to))
                 (at end (not (charge ?s ?l1))) (at end (charge ?s ?l2))))
  (:durative-action leap
    :parameters (?s - shuttle ?from ?to - town ?l1 ?l2 ?l3 - level)
    :duration (= ?duration 50)
    :condition (and (at start (at ?s ?from)) (at start (charge ?s ?l1))
                    (at start (below ?l2 ?l1)) (at start (below ?l3 ?l2)))
    :effect (and (at start (not (at ?s ?from))) (at end (at ?s ?to))
                 (at end (not (charge ?s ?l1))) (at end (charge ?s ?l3))))
  (:durative-action recharge
    :parameters (?s - shuttle ?t - town ?l1 ?l2 - level)
    :duration (= ?duration 40)
    :condition (and (at start (charge ?s ?l1)) (at start (below ?l1 ?l2)) (over all (at ?s ?t)))
    :effect (and (at end (not (charge ?s ?l1))) (at end (charge ?s ?l2)))))

(define (problem fetch-a-rider)
  (:domain shuttles)
  (:objects s1 - shuttle r1 r2 r3 - rider t0 t1 t2 - town l0 l1 l2 l3 l4 l5 l6 - level)
  (:init (at s1 t0) (charge s1 l2)
         (at r1 t2) (at r2 t1) (at r3 t2)
         (below l0 l1) (below l1 l2) (below l2 l3) (below l3 l4) (below l4 l5) (below l5 l6))
  (:goal (and (at s1 t2) (at r1 t1) (at r3 t2))))

;; The fuse can only be fixed while the light is on, and the light goes
;; off when `light` ends: `fix` must run while `light` does. Running
;; actions one after another reaches no plan (the forward phase's search
;; is exhausted); the partial-order search after it overlaps them.
(define (domain light-while-fixing)
  (:requirements :durative-actions)
  (:predicates (lit) (fixed) (match))
  (:durative-action light
    :parameters ()
    :duration (= ?duration 10)
    :condition (at start (match))
    :effect (and (at start (lit)) (at start (not (match))) (at end (not (lit)))))
  (:durative-action fix
    :parameters ()
    :duration (= ?duration 2)
    :condition (over all (lit))
    :effect (at end (fixed))))

(define (problem fuse)
  (:domain light-while-fixing)
  (:init (match))
  (:goal (fixed)))

; A domain with an error: `(closed ?t)` is not a declared predicate.
(define (domain broken)
  (:requirements :typing :durative-actions)
  (:types tank)
  (:predicates (open ?t - tank))
  (:durative-action shut
    :parameters (?t - tank)
    :duration (= ?duration 1)
    :condition (at start (open ?t))
    :effect (and (at end (not (open ?t))) (at end (closed ?t)))))

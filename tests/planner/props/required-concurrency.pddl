; A regression case for analyzer/tests/planner_props.rs (`regressions`).
; expect: solved
;
; Required concurrency: `open` holds only while `hold` runs, and `pass`
; needs it all along, so `pass` must run inside `hold`. No sequential plan
; exists (the breadth-first reference finds none); the planner must find
; the concurrent one, e.g. `0.000: (hold) [5.000]`, `0.010: (pass) [2.000]`.
(define (domain d)
  (:requirements :strips :durative-actions)
  (:predicates (open) (passed))
  (:durative-action hold
    :parameters ()
    :duration (= ?duration 5)
    :condition (and)
    :effect (and (at start (open)) (at end (not (open)))))
  (:durative-action pass
    :parameters ()
    :duration (= ?duration 2)
    :condition (and (at start (open)) (over all (open)))
    :effect (at end (passed))))

(define (problem pr)
  (:domain d)
  (:init)
  (:goal (passed)))

; A HiPOP abstract action whose condition a timed initial literal makes true:
; `inspect` needs the place open when it starts, and the problem opens it at 5.
(define (domain inspect)
  (:requirements :strips :typing :durative-actions :timed-initial-literals :hierarchy)
  (:types robot place)
  (:predicates (at ?r - robot ?p - place) (open ?p - place) (visited ?p - place))
  (:durative-action visit
    :parameters (?r - robot ?p - place)
    :duration (= ?duration 2)
    :condition (and (at start (at ?r ?p)) (over all (open ?p)))
    :effect (at end (visited ?p)))
  (:task inspect
    :parameters (?r - robot ?p - place)
    :duration (= ?duration 2)
    :condition (at start (open ?p))
    :effect (at end (visited ?p)))
  (:method inspect-once
    :parameters (?r - robot ?p - place)
    :task (inspect ?r ?p)
    :subtasks (and (t1 (visit ?r ?p)))))

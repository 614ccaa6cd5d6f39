; Robots inspect wells: an inspection (a HiPOP abstract action) scans the
; well, with a probe the robot carries or, more slowly, by eye, then
; reports.
(define (domain wells)
  (:requirements :strips :typing :durative-actions :hierarchy :method-preconditions)
  (:types robot probe well)
  (:predicates (carries ?r - robot ?p - probe) (scanned ?w - well) (inspected ?w - well))
  (:durative-action probe
    :parameters (?r - robot ?w - well ?p - probe)
    :agent (?r)
    :duration (= ?duration 3)
    :condition (at start (carries ?r ?p))
    :effect (at end (scanned ?w)))
  (:durative-action look
    :parameters (?r - robot ?w - well)
    :agent (?r)
    :duration (= ?duration 6)
    :effect (at end (scanned ?w)))
  (:durative-action report
    :parameters (?r - robot ?w - well)
    :agent (?r)
    :duration (= ?duration 1)
    :condition (at start (scanned ?w))
    :effect (at end (inspected ?w)))
  (:task inspect
    :parameters (?r - robot ?w - well)
    :agent (?r)
    :duration (= ?duration 8)
    :effect (and (at end (scanned ?w)) (at end (inspected ?w))))
  (:method inspect-with-probe
    :parameters (?r - robot ?w - well ?p - probe)
    :task (inspect ?r ?w)
    :precondition (carries ?r ?p)
    :ordered-subtasks (and (t1 (probe ?r ?w ?p)) (t2 (report ?r ?w))))
  (:method inspect-by-eye
    :parameters (?r - robot ?w - well)
    :task (inspect ?r ?w)
    :ordered-subtasks (and (t1 (look ?r ?w)) (t2 (report ?r ?w)))))

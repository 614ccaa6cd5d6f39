; Five undefined predicates and an unused one: six diagnostics. `hipop check`
; prints at most 200 per file (`--max-diagnostics N`), errors first, then
; one I0008 saying how many more there are.
(define (domain many-mistakes)
  (:requirements :strips)
  (:predicates (ready) (idle))
  (:action start :parameters ()
    :precondition (and (ready) (charged) (calibrated))
    :effect (and (running) (logged) (not (ready))))
  (:action stop :parameters ()
    :precondition (stopping)
    :effect (ready)))

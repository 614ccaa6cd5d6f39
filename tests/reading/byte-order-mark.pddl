(define (domain bom) (:predicates (ready) (done) (spare))
  ; Saved by an editor that writes a UTF-8 byte-order mark: the mark is not
  ; part of the first atom, and `spare` (unused) is at line 1, column 51.
  (:action a :parameters () :precondition (ready) :effect (done)))

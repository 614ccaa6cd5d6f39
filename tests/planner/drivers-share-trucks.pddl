; IPC 2002 DriverLog time-simple, problem 3 (domain and problem as in the
; competition). Drivers walk to trucks, board them and drive packages
; around. Ranked by makespan alone, the search expanded 16,000 plans in
; 10 s without a plan: a step that fits in parallel costs nothing in the
; makespan, so it goes through every way of sharing trucks between the
; drivers. The open list ranked by plan size, in turn with it, finds a
; plan in some fifty expansions.
(define (domain driverlog)
  (:requirements :typing :durative-actions) 
  (:types           location locatable - object
    driver truck obj - locatable)

  (:predicates 
    (at ?obj - locatable ?loc - location)
    (in ?obj1 - obj ?obj - truck)
    (driving ?d - driver ?v - truck)
    (link ?x ?y - location) (path ?x ?y - location)
    (empty ?v - truck)
)

(:durative-action LOAD-TRUCK
  :parameters
   (?obj - obj
    ?truck - truck
    ?loc - location)
  :duration (= ?duration 2)
  :condition
   (and 
   (over all (at ?truck ?loc)) (at start (at ?obj ?loc)))
  :effect
   (and (at start (not (at ?obj ?loc))) (at end (in ?obj ?truck))))

(:durative-action UNLOAD-TRUCK
  :parameters
   (?obj - obj
    ?truck - truck
    ?loc - location)
  :duration (= ?duration 2)
  :condition
   (and
        (over all (at ?truck ?loc)) (at start (in ?obj ?truck)))
  :effect
   (and (at start (not (in ?obj ?truck))) (at end (at ?obj ?loc))))

(:durative-action BOARD-TRUCK
  :parameters
   (?driver - driver
    ?truck - truck
    ?loc - location)
  :duration (= ?duration 1)
  :condition
   (and 
   (over all (at ?truck ?loc)) (at start (at ?driver ?loc)) 
  (at start (empty ?truck)))
  :effect
   (and (at start (not (at ?driver ?loc))) 
  (at end (driving ?driver ?truck)) (at start (not (empty ?truck)))))

(:durative-action DISEMBARK-TRUCK
  :parameters
   (?driver - driver
    ?truck - truck
    ?loc - location)
  :duration (= ?duration 1)
  :condition
   (and (over all (at ?truck ?loc)) (at start (driving ?driver ?truck)))
  :effect
   (and (at start (not (driving ?driver ?truck))) 
  (at end (at ?driver ?loc)) (at end (empty ?truck))))

(:durative-action DRIVE-TRUCK
  :parameters
   (?truck - truck
    ?loc-from - location
    ?loc-to - location
    ?driver - driver)
  :duration (= ?duration 10)
  :condition
   (and (at start (at ?truck ?loc-from))
   (over all (driving ?driver ?truck)) (at start (link ?loc-from ?loc-to)))
  :effect
   (and (at start (not (at ?truck ?loc-from))) 
  (at end (at ?truck ?loc-to))))

(:durative-action WALK
  :parameters
   (?driver - driver
    ?loc-from - location
    ?loc-to - location)
  :duration (= ?duration 20)
  :condition
   (and (at start (at ?driver ?loc-from)) 
  (at start (path ?loc-from ?loc-to)))
  :effect
   (and (at start (not (at ?driver ?loc-from)))
  (at end (at ?driver ?loc-to))))
 
)

(define (problem DLOG-2-2-4)
  (:domain driverlog)
  (:objects
  driver1 - driver
  driver2 - driver
  truck1 - truck
  truck2 - truck
  package1 - obj
  package2 - obj
  package3 - obj
  package4 - obj
  s0 - location
  s1 - location
  s2 - location
  p0-1 - location
  p2-0 - location
  p2-1 - location
  )
  (:init
  (at driver1 s1)
  (at driver2 s0)
  (at truck1 s1)
  (empty truck1)
  (at truck2 s2)
  (empty truck2)
  (at package1 s0)
  (at package2 s0)
  (at package3 s1)
  (at package4 s1)
  (path s0 p0-1)
  (path p0-1 s0)
  (path s1 p0-1)
  (path p0-1 s1)
  (path s2 p2-0)
  (path p2-0 s2)
  (path s0 p2-0)
  (path p2-0 s0)
  (path s2 p2-1)
  (path p2-1 s2)
  (path s1 p2-1)
  (path p2-1 s1)
  (link s1 s0)
  (link s0 s1)
  (link s1 s2)
  (link s2 s1)
  (link s2 s0)
  (link s0 s2)
)
  (:goal (and
  (at driver2 s2)
  (at truck1 s1)
  (at truck2 s2)
  (at package1 s1)
  (at package2 s1)
  (at package3 s2)
  ))

(:metric minimize (total-time))

)

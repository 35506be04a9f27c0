; The same domain with its derived predicates substituted by hand; the closure of the
; recursive `heavier` is listed in compiled-problem.pddl.
(define (domain derived-blocks)
  (:requirements :typing :negative-preconditions :existential-preconditions
                 :probabilistic-effects)
  (:types block)
  (:constants table - block)
  (:predicates (on ?a - block ?b - block) (fixed ?a - block) (heavier ?a - block ?b - block))
  (:action move
    :parameters (?a - block ?from - block ?to - block)
    :precondition (and (on ?a ?from) (or (= ?a table) (not (exists (?b - block) (on ?b ?a))))
                       (or (= ?to table) (not (exists (?b - block) (on ?b ?to)))) (not (= ?a ?to))
                       (not (= ?from ?to)) (not (= ?a table)) (not (fixed ?a))
                       (not (heavier ?a ?to)))
    :effect (and (not (on ?a ?from))
                 (probabilistic 3/4 (on ?a ?to) 1/4 (on ?a table))))
  (:action fix
    :parameters (?a - block ?b - block)
    :precondition (and (on ?a ?b) (not (fixed ?a)) (on ?b table))
    :effect (fixed ?a))
)

; above-domain.pddl written without recursion: `above` is unrolled by hand to chains of
; at most four `on` steps (above1 .. above4), exact for four blocks and the table; all
; definitions are non-recursive, so grounding substitutes them away.
(define (domain above-blocks-unrolled)
  (:requirements :typing :negative-preconditions :existential-preconditions
                 :probabilistic-effects :derived-predicates)
  (:types block)
  (:constants table - block)
  (:predicates (on ?a - block ?b - block) (clear ?a - block) (above ?a - block ?b - block)
               (above1 ?a - block ?b - block) (above2 ?a - block ?b - block)
               (above3 ?a - block ?b - block) (done))
  (:derived (clear ?a - block) (or (= ?a table) (not (exists (?b - block) (on ?b ?a)))))
  (:derived (above1 ?a - block ?b - block) (on ?a ?b))
  (:derived (above2 ?a - block ?b - block)
            (or (on ?a ?b) (exists (?c - block) (and (on ?a ?c) (above1 ?c ?b)))))
  (:derived (above3 ?a - block ?b - block)
            (or (on ?a ?b) (exists (?c - block) (and (on ?a ?c) (above2 ?c ?b)))))
  (:derived (above ?a - block ?b - block)
            (or (on ?a ?b) (exists (?c - block) (and (on ?a ?c) (above3 ?c ?b)))))
  (:action move
    :parameters (?a - block ?from - block ?to - block)
    :precondition (and (on ?a ?from) (clear ?a) (clear ?to) (not (= ?a ?to))
                       (not (= ?from ?to)) (not (= ?a table)))
    :effect (and (not (on ?a ?from))
                 (probabilistic 3/4 (on ?a ?to) 1/4 (on ?a table))))
  (:action celebrate  ; a tower of three blocks stands somewhere
    :parameters (?x - block ?y - block ?z - block)
    :precondition (and (above ?x ?y) (above ?y ?z) (not (= ?z table)))
    :effect (done))
)

; Blocksworld with a recursive derived predicate over a fluent (PDDL 2.2 axioms):
; `above` is the transitive closure of `on`, which every move changes, so it is
; recomputed in every state (a ground axiom program; docs/ir.md). `clear` is derived
; too (non-recursive: substituted). A move may drop the block on the table.
(define (domain above-blocks)
  (:requirements :typing :negative-preconditions :existential-preconditions
                 :probabilistic-effects :derived-predicates)
  (:types block)
  (:constants table - block)
  (:predicates (on ?a - block ?b - block) (clear ?a - block) (above ?a - block ?b - block)
               (done))
  (:derived (clear ?a - block) (or (= ?a table) (not (exists (?b - block) (on ?b ?a)))))
  (:derived (above ?a - block ?b - block)
            (or (on ?a ?b) (exists (?c - block) (and (on ?a ?c) (above ?c ?b)))))
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

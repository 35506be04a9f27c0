; Stacking blocks with derived predicates (PDDL 2.2 axioms): `clear`, `stacked` and
; `base` are defined from the fluents `on` and `fixed`. Probabilistic: a move may drop
; the block on the table. `heavier` is recursive (the transitive closure of the static
; `weighs-more`): a block may not go onto a lighter one.
(define (domain derived-blocks)
  (:requirements :typing :negative-preconditions :existential-preconditions
                 :probabilistic-effects :derived-predicates)
  (:types block)
  (:constants table - block)
  (:predicates (on ?a - block ?b - block) (clear ?a - block) (fixed ?a - block)
               (base ?a - block) (stacked ?a - block ?b - block)
               (weighs-more ?a - block ?b - block) (heavier ?a - block ?b - block))
  (:derived (clear ?a - block) (or (= ?a table) (not (exists (?b - block) (on ?b ?a)))))
  (:derived (stacked ?a - block ?b - block) (and (on ?a ?b) (not (fixed ?a))))
  (:derived (base ?a - block) (on ?a table))
  (:derived (heavier ?a - block ?b - block)
            (or (weighs-more ?a ?b) (exists (?c - block) (and (weighs-more ?a ?c) (heavier ?c ?b)))))
  (:action move
    :parameters (?a - block ?from - block ?to - block)
    :precondition (and (on ?a ?from) (clear ?a) (clear ?to) (not (= ?a ?to))
                       (not (= ?from ?to)) (not (= ?a table)) (not (fixed ?a))
                       (not (heavier ?a ?to)))
    :effect (and (not (on ?a ?from))
                 (probabilistic 3/4 (on ?a ?to) 1/4 (on ?a table))))
  (:action fix
    :parameters (?a - block ?b - block)
    :precondition (and (stacked ?a ?b) (base ?b))
    :effect (fixed ?a))
)

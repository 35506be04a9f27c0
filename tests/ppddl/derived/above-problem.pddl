(define (problem above-4) (:domain above-blocks)
  (:objects a b c d - block)
  (:init (on a b) (on b table) (on c d) (on d table))
  (:goal (and (done) (above a c) (above c b))))

"""stampc.solvers."""

"""stampc.semantics."""

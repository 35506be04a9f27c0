"""stampc.refine."""

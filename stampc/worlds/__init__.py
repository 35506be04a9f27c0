"""stampc.worlds."""

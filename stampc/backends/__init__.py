"""stampc.backends."""

"""stampc.backends.ppddl."""

"""stampc.syntax."""

"""stampc.commands."""

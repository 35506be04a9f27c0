"""stampc.worlds.plane2d."""

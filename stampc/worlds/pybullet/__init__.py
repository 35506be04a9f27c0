"""stampc.worlds.pybullet."""

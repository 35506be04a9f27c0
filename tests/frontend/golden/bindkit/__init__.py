"""Bound functions with the mistakes the E6xx/W407 golden cases show."""

"""Bound functions of the golden cases (read by `check` with `ast`, never imported)."""

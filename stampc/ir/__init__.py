"""Intermediate representations: lifted (`lifted`) and grounded (`grounded`)."""

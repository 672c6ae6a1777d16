"""Reproduced experiments; each writes a run directory (DESIGN.md's contract)."""

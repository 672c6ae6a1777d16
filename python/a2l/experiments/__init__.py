"""Reproduced experiments; each writes a run directory (``a2l.rundir``)."""

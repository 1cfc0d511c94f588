"""Finite displacement: position solver, continuation, event location, branch switching (paper §IV-A, §V)."""

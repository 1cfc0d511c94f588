"""The curve toolkit: one corrector, one singular-point locator, one tracer with event objects.

Mechanism-free numerics shared by paths (:mod:`symkin.paths`), maps (:mod:`symkin.workspace`)
and global solutions (:mod:`symkin.solutions`).  It imports only the numeric layer, the
tolerances, the kinds and the errors; a problem is given as functions of a dimensionless
unknown ``z`` (residual and Jacobian, CasADi Functions where derivatives are needed).

* :mod:`symkin.curves.corrector` — Gauss–Newton on one point or on a batch of points.
"""

"""The curve toolkit: one corrector, one singular-point locator, one tracer with event objects.

Mechanism-free numerics shared by paths (:mod:`symkin.paths`), maps (:mod:`symkin.workspace`)
and global solutions (:mod:`symkin.solutions`), and by the numeric layer's projections onto the
closure.  It imports only the tolerances, the kinds and the errors (it sits below the numeric
layer; ``tests/test_architecture.py`` checks it); a problem is given as functions of a dimensionless
unknown ``z`` (residual and Jacobian, CasADi Functions where derivatives are needed).

* :mod:`symkin.curves.corrector` — Gauss–Newton on one point or on a batch of points;
* :mod:`symkin.curves.stepper` — pseudo-arclength continuation (its corrections are the corrector's);
* :mod:`symkin.curves.locate` — roots and minima of a test along a curve, the one singular-point
  locator (rank drop ``k``, exact CasADi derivatives, deflation), the closure polish;
* :mod:`symkin.curves.branches` — the half-branches leaving a vertex;
* :mod:`symkin.curves.events` — event types (test, locator, kind) and stop rules;
* :mod:`symkin.curves.tracer` — the one tracer: stepper + events + merging + stop rules.
"""

"""Workspace and joint-space singularity maps (paper §VI, Figs. 14-16).

``system`` (the map's square position problem), ``grid`` (continuation of each working
mode over the grid, indicators from the one analysis core), ``maps`` (the frozen
:class:`~symkin.workspace.maps.WorkspaceMap`, JSON / npz) and ``loci`` (refinement to
exact curves, the driver; its parts: ``locus_problems``, ``refine_data``, ``locate``,
``im_points``, ``reseed``, ``cusps``, ``locus_events``, ``tracing`` (on the one tracer,
:func:`symkin.curves.tracer.trace_curve`), ``singular_points``; ``quadtree`` subdivides
cells in batches).

LIM points of a map (paper §III-B.3, §IV-C) — the rule, **not implemented yet**: a link is in
LIM where every kinematic parameter of its motion is null whatever the inputs, i.e. its rows of
the motion-space basis ``V`` / ``Ω`` vanish; a parameter ``u`` is null for every motion exactly
when the row ``e_u`` lies in the row space of the constraint Jacobian ``J_S``:
``J_Sᵀ ψ + e_u = 0`` for some ``ψ``.  For a link with one independent parameter (a link turning
about a fixed pivot: its ``ω``) these are ``F`` conditions on the ``F``-dimensional configuration
space: the link locks on a set of codimension up to ``F``, so a map (a 2-D slice, ``F − 2``
coordinates held) meets it in isolated points when ``F = 2`` (or when a held value makes the set
meet the slice), and generically not at all otherwise.  To report them, a map would: evaluate per
link the relative LIM indicator ``max_u ‖V_u‖`` (the link's rows of an orthonormal motion-space
basis, dimensionless velocities; one batch per grid wave, as the IM indicator); take its grid
minima among the eight neighbours as candidates; subdivide and screen them as IM minima are (one
batched Gauss–Newton polish of ``(Φ_S/ℓ, holds, J_Sᵀψ + e_u) = 0`` in ``(q/ℓ, ψ)``, refined only
below :attr:`~symkin.tolerances.Tolerances.event_threshold`); and report a located configuration
inside the box that the core classifies LIM (``"LIM"`` in ``analyze(...).types``) as a point of
kind ``"LIM"`` (:attr:`symkin.kinds.Kind.LIM`), merged by axis values as IM points are.
"""

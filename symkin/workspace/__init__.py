"""Workspace and joint-space singularity maps (paper §VI, Figs. 14-16).

``system`` (the map's square position problem), ``grid`` (continuation of each working
mode over the grid, indicators from the one analysis core), ``maps`` (the frozen
:class:`~symkin.workspace.maps.WorkspaceMap`, JSON / npz) and ``loci`` (refinement to
exact curves, the driver; its parts: ``locus_problems``, ``refine_data``, ``locate``,
``im_points``, ``lim_points``, ``reseed``, ``cusps``, ``locus_events``, ``tracing`` (on the one tracer,
:func:`symkin.curves.tracer.trace_curve`), ``singular_points``; ``quadtree`` subdivides
cells in batches).

LIM points of a map (paper §III-B.3, §IV-C; ``lim_points``, step 4b of ``loci``): a planar link
turning about a fixed pivot is in LIM where its angular rate is null whatever the inputs, i.e. its
unit row ``u`` lies in the row space of ``J_S`` (``J_Sᵀψ + u = 0``): ``F`` conditions, a set of
codimension up to ``F`` that a map meets in isolated points when ``F = 2``.  Implemented: the grid
evaluates per pivoted link the relative LIM indicator (``link_speed`` of the link's free-node rows of
an orthonormal motion-space basis; one batch per wave) and keeps the smallest; its minima along grid
lines are candidates; one batched Gauss–Newton polish of ``(Φ_S/ℓ, J_Sᵀψ + u) = 0`` (on the slice) in
``(q/ℓ, ψ)`` per link locates them (kept below :attr:`~symkin.tolerances.Tolerances.event_threshold`,
in the box); a located configuration that :func:`symkin.analyze` classifies LIM with that link in
``locked_links`` is a point of kind ``"LIM"`` (:attr:`symkin.kinds.Kind.LIM`) with its
``locked_links``.  Not detected: links without a fixed pivot, spatial links, LIM sets meeting a slice
(``F > 2``) along curves, points on the grid's outer ring.
"""

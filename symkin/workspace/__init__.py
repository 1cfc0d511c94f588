"""Workspace and joint-space singularity maps (paper §VI, Figs. 14-16).

``system`` (the map's square position problem), ``grid`` (continuation of each working
mode over the grid, indicators from the one analysis core), ``maps`` (the frozen
:class:`~symkin.workspace.maps.WorkspaceMap`, JSON / npz) and ``loci`` (refinement to
exact curves).
"""

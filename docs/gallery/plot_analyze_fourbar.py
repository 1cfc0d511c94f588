"""
Analyse the appendix four-bar
=============================

Read the paper's appendix four-bar from its model file, analyse the configuration, then analyse
the catalogue's four-bar at a dead centre (DKP-output and LIM), print the report in sentences,
and draw the mechanism with its motion space.
"""
# %%
from pathlib import Path

import symkin

root = Path(symkin.__file__).resolve().parent.parent   # the repository's root
mech = symkin.read_model(root / "papers_examples" / "fourbar_appendix.toml")
result = symkin.analyze(mech)
print(result.dof, result.types)          # 1 ()

# %%
# At a dead centre the rocker is locked: the output rotation depends on nothing.
dead = symkin.catalogue.get("fourbar_dead_centre")
r = symkin.analyze(dead)
print(r.types, [rel.as_dict() for rel in r.output_relations])
print(symkin.render_text(r))

# %%
# The geometric matrix of the paper's eq. (A6), with the boundary conditions.
G = symkin.geometric_matrix(mech, boundary=True)
print(G.shape)

# %%
# The mechanism at the dead centre, with its motion-space vector (eq. 9): the crank's end moves,
# the rocker's end C does not (the rocker is locked: LIM).
from symkin.plots import draw_mechanism

ax = draw_mechanism(dead, motion=symkin.motion_space(dead), title="four-bar at a dead centre")

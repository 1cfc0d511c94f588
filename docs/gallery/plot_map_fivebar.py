"""
A workspace map of the five-bar
===============================

Map the singularity indicators of the catalogue five-bar over the position of its end point P
(paper §VI), in two working modes (the model's, and leg 1 in its other elbow), refined to exact
singular curves. A small grid (n = 31) keeps the example short.
"""
# %%
import symkin
from symkin.plots import plot_map

mech = symkin.catalogue.get("five_bar")
elbow = mech.with_coordinates({"B1": [0.0, 0.0]})   # a second working mode
m = symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=31,
                         seeds=[elbow])
print(len(m.modes), "working modes")
print(m.counts())

# %%
# The DKP-input test function of the second mode, with its traced curves and the workspace boundary.
ax = plot_map(m, mode=1, indicator="dkp_input")

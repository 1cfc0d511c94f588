"""
A workspace map of the five-bar
===============================

Map the singularity indicators of the catalogue five-bar over the position of its end point P
(paper §VI), in two working modes (the model's, and leg 1 in its other elbow), refined to exact
singular curves. A small grid (n = 51) keeps the example short.
"""
# %%
import symkin
from symkin.plots import plot_map

mech = symkin.catalogue.get("five_bar")
elbow = mech.with_coordinates({"B1": [0.0, 0.0]})   # a second working mode
m = symkin.workspace_map(mech, x="velocity:P.x=-3.5:3.5", y="velocity:P.y=0.2:4.4", n=51,
                         seeds=[elbow])
print(len(m.modes), "working modes")
print(m.counts())

# %%
# The IM indicator (log scale) of the model's mode, and the DKP-output test function of the second
# mode, each with the traced curves and the mode's workspace boundary.
import matplotlib.pyplot as plt

fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
plot_map(m, mode=0, indicator="im_indicator", ax=ax1)
plot_map(m, mode=1, indicator="dkp_output", ax=ax2)

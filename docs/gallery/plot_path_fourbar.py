"""
A path of a four-bar and its singular events
============================================

Turn the appendix four-bar's crank through a full turn (finite displacements), locate every
singular configuration on the way exactly, and plot the indicators with the located events and
the node traces.
"""
# %%
import matplotlib.pyplot as plt

import symkin
from symkin.plots import plot_indicators, plot_traces

mech = symkin.catalogue.get("fourbar_appendix")
path = symkin.trace(mech, input="rotation:crank", start=0, stop=360, unit="deg")
for i, event in enumerate(path.events, 1):
    print(i, event.kind, path.values(event))

# %%
fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 10), layout="constrained")
plot_indicators(path, ax=ax1)
plot_traces(path, ax=ax2)

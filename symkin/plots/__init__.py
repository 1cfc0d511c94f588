"""Plots of symkin results (matplotlib, imported only when a function is called).

Every function takes ``ax=None`` (a new figure when ``None``), draws results it is given,
and returns the Axes (networkx ``draw`` style):

* :func:`plot_indicators` — IM indicator and signed DKP test functions along a path, with
  the located events (paper Figs. 3c, 10);
* :func:`plot_traces` — node traces of a path with its singular configurations (Fig. 5);
* :func:`plot_input_output` — the input–output curve of a path with its events on it;
* :func:`draw_mechanism` — a mechanism with motion-space vectors as arrows (Figs. 4, 6, 7,
  11-13);
* :func:`draw_leg_lines` — the legs' lines of a planar parallel manipulator and their common
  point (drawn on the type-2 panels of a path);
* :func:`plot_event_configurations` — the mechanism at each located singular event of a
  path, one small panel per event, same axes limits;
* :func:`save_path_figures` — indicators, traces and the event panels in one PNG
  (``symkin path ... --plot FILE.png``);
* :func:`plot_map` — one indicator of one working mode of a singularity map (``log |IM|``, signed
  DKP test functions) with the traced curves and the mode's workspace boundary (Figs. 14, 16);
* :func:`plot_im_surface` — the IM indicator of a mode as a 3-D surface (Fig. 15);
* :func:`plot_seed` — the mechanism at a mode's seed configuration, in its workspace;
* :func:`save_map_figure` — columns = modes, rows = indicators (+ mechanism) in one PNG, one column wide
  (``symkin map ... --plot FILE.png``);
* :func:`~symkin.plots.extra.require_matplotlib` — the clear error when the plots extra is missing.
"""
from symkin.plots.mechanism import draw_leg_lines, draw_mechanism
from symkin.plots.maps import plot_im_surface, plot_map, plot_seed, save_map_figure
from symkin.plots.paths import (plot_event_configurations, plot_indicators, plot_input_output, plot_traces,
                                save_path_figures)

__all__ = ["draw_mechanism", "draw_leg_lines", "plot_event_configurations", "plot_indicators", "plot_input_output",
           "plot_traces", "save_path_figures",
           "plot_map", "plot_im_surface", "plot_seed", "save_map_figure"]

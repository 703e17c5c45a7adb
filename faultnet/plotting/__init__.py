"""Plots: magnitude distributions, slip profiles, time series, return maps, the graph (and a
network of faults coloured by fault), and the seismicity figures (waiting times, mainshock
stacks, distance profiles).

Every function takes ``ax=None`` (a new figure) and returns the matplotlib Axes.
"""

from faultnet.plotting.figures import (
    plot_magnitude_distribution,
    plot_profiles,
    plot_return_map,
    plot_time_series,
)
from faultnet.plotting.graphs import plot_faults, plot_graph
from faultnet.plotting.seismicity import plot_distance_profile, plot_interevent_times, plot_stack

__all__ = [
    "plot_distance_profile",
    "plot_faults",
    "plot_graph",
    "plot_interevent_times",
    "plot_magnitude_distribution",
    "plot_profiles",
    "plot_return_map",
    "plot_stack",
    "plot_time_series",
]

"""Parameter sweeps: a TOML file of points, run one by one into a sweep folder
(one catalog each, with a lock and a manifest), then summarised into one table.

:func:`~faultnet.sweep` runs a sweep and :func:`~faultnet.summarize` summarises it.
"""

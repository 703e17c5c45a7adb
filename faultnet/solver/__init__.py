"""The engine: run options and accuracy, the Simulator, the Numba kernels, results.

:func:`~faultnet.simulate` and :class:`~faultnet.Simulator` turn a model into
events; ``_kernels/`` holds only kernel code; :mod:`~faultnet.solver.dynamics` small systems.
"""

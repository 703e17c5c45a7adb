"""The command line: ``faultnet simulate``, ``info``, ``sweep`` and the rest.

:mod:`~faultnet.cli.parser` declares the arguments; :mod:`~faultnet.cli.commands`
checks them, runs the command and turns every faultnet error into one line.
"""

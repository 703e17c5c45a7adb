"""Files: Parquet catalogs and their checks, catalog summaries, atomic writes, locks.

Nothing here runs a model; the solver reads a stored state from a catalog and
the long runs write their chunks and outputs through these modules.
"""

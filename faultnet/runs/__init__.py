"""Long runs on disk: one LongRun starts, resumes, checkpoints, merges and verifies a run;
graph specs name the model of a run; ``sweep/`` runs many of them into one folder.

:func:`~faultnet.simulate_to_parquet` and ``faultnet simulate --out`` run through here.
"""

"""tavis_baseline: the reference learned baseline for TAVIS-C++ (docs/baselines.md).

A LeRobot v3.0 loader for `tavis demos` datasets without LeRobot (dataset.py, parquet.py, video.py,
windows.py), a small image+state -> action-chunk policy with LeRobot's interface (policy.py,
config.py), its trainer (`python3 -m tavis_baseline.train`) and server (`python3 -m tavis_baseline.serve`).
"""

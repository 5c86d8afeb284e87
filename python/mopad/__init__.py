"""OpenMoPAD from Python.

`mopad.dataset` reads the datasets `mopad dataset RUN_DIR -o DIR` writes (docs/dataset.md):
registered TLS scans as numpy arrays with per-point semantic and instance labels from the truth.
Needs numpy only.
"""

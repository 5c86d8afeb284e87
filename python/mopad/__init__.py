"""OpenMoPAD from Python (docs/python.md).

- `mopad.dataset` (numpy only) reads the datasets `mopad dataset RUN_DIR -o DIR` writes
  (docs/dataset.md): registered TLS scans with per-point semantic and instance labels.
- The compiled part (mopad._mopad, pybind11; built when Debian's pybind11-dev is there):
  `World` (a scene with its truth), `scan()` (a TLS scan as numpy arrays, its truth apart),
  `Robot` (the simulated robot as a step API), `generate_scene()`, `run()` (the main job),
  `evaluate()`.
"""
try:
    from ._mopad import InputError, Robot, World, evaluate, generate_scene, run, scan  # noqa: F401
except ImportError as _e:  # the pure-Python part works without the module
    _missing = _e

    def __getattr__(name):
        if name in ("InputError", "Robot", "World", "evaluate", "generate_scene", "run", "scan"):
            raise ImportError(f"mopad.{name} needs the compiled module mopad._mopad "
                              f"(build with Debian's pybind11-dev): {_missing}")
        raise AttributeError(name)

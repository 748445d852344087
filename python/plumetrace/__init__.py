"""plumetrace: odor-plume tracking simulator, from Python.

The C++ core does the work; this package is a thin layer over it. Import path: the build's
``build/python`` folder (``PYTHONPATH=build/python /usr/bin/python3``).

    import plumetrace as pt
    s = pt.Scenario()                      # the built-in defaults (the paper's setup)
    s.wind_sensor.sigma_a = 0.3            # any key, as a nested attribute ...
    s["controller.algorithm"] = "casting"  # ... or by its dotted path
    r = pt.run(s, seed=1, trial=0)         # metrics as in `plumetrace run --json`
    r["trajectory"]["x"]                   # NumPy arrays
    rows = pt.sweep("studies/lochmatter2008/sets/A.toml", runs=4)
    rows.to_numpy()["success"]             # or rows.to_pandas() when pandas is installed

Submodules: ``plumetrace.controllers`` (write your own controller), ``plumetrace.env``
(a Gymnasium-style environment), ``plumetrace.plots`` (matplotlib helpers),
``plumetrace.report`` (the reproduction report, ``python3 -m plumetrace.report OUT_DIR``).
"""

__all__ = ["ConfigError", "MAX_THREADS", "Param", "Scenario", "ScenarioWarning", "SweepRows",
           "algorithms", "register_controller", "result_fields", "run", "sweep", "__version__"]


def __getattr__(name):
    # why: lazy, so that plumetrace.report works from the source tree without the C++ module
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'plumetrace' has no attribute {name!r}")

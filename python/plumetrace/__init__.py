"""plumetrace: odor-plume tracking simulator, from Python.

The C++ core does the work; this package is a thin layer over it. Install it with
``pip install --no-build-isolation --no-index .`` (README, "From Python"; docs/python.md), or use
the build's copy: ``PYTHONPATH=build/python /usr/bin/python3``.

    import plumetrace as pt
    s = pt.Scenario()                      # the built-in defaults (the paper's setup)
    s.wind_sensor.sigma_a = 0.3            # any key, as a nested attribute ...
    s["controller.algorithm"] = "casting"  # ... or by its dotted path
    r = pt.run(s, seed=1, trial=0)         # metrics as in `plumetrace run --json`
    r["trajectory"]["x"]                   # NumPy arrays
    from plumetrace.studies import lochmatter2008 as paper
    rows = pt.sweep(paper.sets["A"], runs=4)   # the paper's sets ship with the package
    rows.to_numpy()["success"]             # or rows.to_pandas()
    m = pt.probe(grid="arena")             # the plume alone: detection map as NumPy arrays
    rows = pt.sweep({"surge_cast.d_lost": [0.2, 0.6]}, runs=20)   # a sweep as a dict of axes
    rows.summary()                         # Wilson 95% of success, bootstrap 95% of overhead
    pt.report(rows, out="out/mine")        # report.html, report.md, report.csv, figures/

Submodules: ``plumetrace.studies`` (the studies' sweep files), ``plumetrace.controllers`` (write
your own controller), ``plumetrace.env`` (a Gymnasium-style environment), ``plumetrace.plots``
(matplotlib helpers), ``plumetrace.report`` (the reproduction report,
``python3 -m plumetrace.report OUT_DIR``, and ``plumetrace.report(rows, out=...)`` for any
sweep), ``plumetrace.sweeps`` (dict sweeps and their statistics), ``plumetrace.calibrate`` (the
calibration of the paper's unknowns), ``plumetrace.evidence`` (the statistical tests studies decide
with), ``plumetrace.benchmark`` (a benchmark's leaderboard, ``python3 -m
plumetrace.benchmark.leaderboard OUT``, and the comparison of two results). ``dir(plumetrace)``
lists all of it.
"""

__all__ = ["ConfigError", "MAX_THREADS", "Param", "Scenario", "ScenarioWarning", "StoreError",
           "SweepRows", "algorithms", "probe", "register_controller", "report", "result_fields",
           "run", "sweep", "__version__"]

# why: with the source tree's package first on the path and a build's copy after it (what
# `plumetrace study` gives a report), the compiled module plumetrace._core is found in the
# build's copy; a package alone on the path is unchanged
__path__ = __import__("pkgutil").extend_path(__path__, __name__)

# the submodules a user imports, loaded on first use
_SUBMODULES = ("benchmark", "calibrate", "controllers", "env", "evidence", "learn", "plots",
               "report", "studies", "sweeps", "team_env", "vector")


def __getattr__(name):
    # why: lazy, so that plumetrace.report works from the source tree without the C++ module;
    # the report package is callable: plumetrace.report(...) for any sweep
    if name in _SUBMODULES:
        import importlib

        return importlib.import_module(f".{name}", __name__)
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'plumetrace' has no attribute {name!r}")


def __dir__():
    """The API (__all__) and the submodules, as a user sees them; no private names."""
    dunders = (n for n in globals() if n.startswith("__"))
    return sorted({*__all__, *_SUBMODULES, *dunders})

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

Submodules: ``plumetrace.studies`` (the studies' sweep files), ``plumetrace.controllers`` (write
your own controller), ``plumetrace.env`` (a Gymnasium-style environment), ``plumetrace.plots``
(matplotlib helpers), ``plumetrace.report`` (the reproduction report,
``python3 -m plumetrace.report OUT_DIR``).
"""

__all__ = ["ConfigError", "MAX_THREADS", "Scenario", "SweepRows", "algorithms", "probe",
           "result_fields", "run", "sweep", "__version__"]


def __getattr__(name):
    # why: lazy, so that plumetrace.report works from the source tree without the C++ module
    if name in __all__:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'plumetrace' has no attribute {name!r}")

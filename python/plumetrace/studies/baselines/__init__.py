"""The baselines study (studies/baselines): every algorithm built into the library, side by side.

    from plumetrace.studies import baselines
    pt.sweep(baselines.sets["L"], runs=5)  # sets: by each sweep file's name, study.toml's order
    baselines.folder                       # `plumetrace study` runs this folder

report.py, which draws its report, lives in the repository's studies/baselines/ and ships
here (cmake/python_package.cmake).
"""

from .. import _subpackage_path

__path__ = _subpackage_path(__path__, "baselines")


def __getattr__(name):
    from .. import folder, sets

    if name == "folder":
        return folder("baselines")
    if name == "sets":
        return sets("baselines")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

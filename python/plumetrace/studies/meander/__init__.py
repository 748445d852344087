"""The meander study (studies/meander): the three algorithms in a meandering wind.

    from plumetrace.studies import meander
    pt.sweep(meander.sets["M"], runs=5)   # sets: by each sweep file's name, study.toml's order
    meander.folder                        # `plumetrace study` runs this folder

report.py, which draws its "Beyond the paper" report, lives in the repository's
studies/meander/ and ships here (cmake/python_package.cmake).
"""

from .. import _subpackage_path

__path__ = _subpackage_path(__path__, "meander")


def __getattr__(name):
    from .. import folder, sets

    if name == "folder":
        return folder("meander")
    if name == "sets":
        return sets("meander")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

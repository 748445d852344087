"""Lochmatter & Martinoli (2008): the nine experiment sets, the readings and the report.

    from plumetrace.studies import lochmatter2008 as paper
    pt.sweep(paper.sets["A"], runs=10)   # sets: {"A": Path(".../sets/A.toml"), ..., "I": ...}
    paper.presets["calibrated"]          # presets: {"calibrated": Path(...), ...} (readings)
    paper.folder / "study.toml"          # what `plumetrace reproduce` runs

report_sections.py, the sections of its report, lives in the repository's
studies/lochmatter2008/ and ships here (cmake/python_package.cmake).
"""

from .. import _subpackage_path

__path__ = _subpackage_path(__path__, "lochmatter2008")


def __getattr__(name):
    # why: lazy, so that importing report_sections (the report) reads no file
    from .. import folder, sets

    if name == "folder":
        return folder("lochmatter2008")
    if name == "sets":
        return sets("lochmatter2008")
    if name == "presets":
        return {p.stem: p for p in sorted((folder("lochmatter2008") / "presets").glob("*.toml"))}
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

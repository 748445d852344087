"""The reports: the paper's reproduction (this package) and any sweep's (report/sweep.py).

    python3 -m plumetrace.report OUT_DIR    (the package installed; docs/report.md): the paper's
    plumetrace.report(rows_or_sweep, store=..., out=...)    any sweep's, from Python

reads OUT_DIR/summary.json (and OUT_DIR/sensitivity.json when it exists) and writes
OUT_DIR/report.html (self-contained: every figure is embedded as a data URI), OUT_DIR/report.md
and the figures it links, OUT_DIR/figures/*.png. The file formats are described in docs/report.md.

data.py reads and checks the inputs, figures.py draws, page.py renders and writes; what the
report says comes from plumetrace.studies.lochmatter2008.report_sections. Only the standard
library, numpy and matplotlib (Agg) are used.
"""

from __future__ import annotations

import sys
import types
from pathlib import Path
from typing import Union

from .._files import output_folder
from .data import Point, ReportError, fmt_overhead, load_inputs
from .page import REPO_ROOT, render_html, render_markdown, write_pages
from plumetrace.studies.lochmatter2008.report_sections import (document, failure_sentence,
                                                               report_title)

__all__ = ["Point", "REPO_ROOT", "ReportError", "build_report", "failure_sentence",
           "fmt_overhead", "render_html", "render_markdown", "report_title"]


def build_report(out_dir: Union[str, Path]) -> list:
    """Builds report.html, report.md and figures/*.png in out_dir; returns the written paths.

    Raises ReportError (whose message names the file) if summary.json is missing or malformed,
    or if sensitivity.json exists but is malformed.
    """
    out_dir = Path(out_dir)
    summary, sens = load_inputs(out_dir)
    fig_dir = output_folder(out_dir / "figures", "the report's figures")
    figures: list = []
    title, intro, sections = document(out_dir, fig_dir, summary, sens, figures)
    return write_pages(out_dir, title, intro, sections) + figures


class _CallableModule(types.ModuleType):
    """This package, callable: ``plumetrace.report(...)`` draws the report of any sweep
    (report_sweep, report/sweep.py), while ``python3 -m plumetrace.report OUT`` draws the
    paper's."""

    def __call__(self, *args, **kwargs):
        # why: imported here, so that python3 -m plumetrace.report.sweep runs it fresh
        from .sweep import report_sweep

        return report_sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

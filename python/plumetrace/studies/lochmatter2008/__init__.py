"""Lochmatter & Martinoli (2008): report_sections.py, the sections of its report."""

from pathlib import Path

# why: report_sections.py lives in the repository's studies/lochmatter2008/ and the build copies
# it here; from the source tree (PYTHONPATH=python, as `plumetrace reproduce` runs the report)
# it is found in the repository's folder
_in_repository = Path(__file__).resolve().parents[4] / "studies" / "lochmatter2008"
if _in_repository.is_dir():
    __path__.append(str(_in_repository))

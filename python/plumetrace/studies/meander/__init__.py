"""The meander study (studies/meander): report.py draws its "Beyond the paper" report."""

from pathlib import Path

# why: report.py lives in the repository's studies/meander/ and the build copies it here; from
# the source tree (PYTHONPATH=python) it is found in the repository's folder
_in_repository = Path(__file__).resolve().parents[4] / "studies" / "meander"
if _in_repository.is_dir():
    __path__.append(str(_in_repository))

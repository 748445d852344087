"""Examples that ship with the package, importable from any folder:

    from plumetrace.examples.python_surge_cast import SurgeCast   # examples/python_surge_cast.py

The files live in the repository's examples/ folder and ship here (cmake/python_package.cmake);
from the source tree (PYTHONPATH=python) they are read there.
"""

from pathlib import Path

_repository = Path(__file__).resolve().parents[3] / "examples"
if not (Path(__path__[0]) / "python_surge_cast.py").is_file() and _repository.is_dir():
    __path__.append(str(_repository))

"""The studies plumetrace re-runs, one subpackage each, with their sweep files and reports.

    import plumetrace as pt
    from plumetrace.studies import lochmatter2008 as paper
    rows = pt.sweep(paper.sets["A"], runs=10)    # the paper's set A, from any folder
    paper.folder                                 # its study.toml, sets/, presets/
    paper.presets["calibrated"]                  # a reading of the paper (a partial scenario)

The files ship with the package (`pip install .`, or the build's build/python); from the
source tree (PYTHONPATH=python) they are read in the repository's studies/ folder.
"""

from pathlib import Path

__all__ = ["folder", "names", "sets"]

_HERE = Path(__file__).resolve().parent


def names():
    """The names of the studies shipped (each a subpackage: lochmatter2008, meander)."""
    return sorted(p.name for p in _HERE.iterdir() if (p / "__init__.py").is_file())


def folder(name):
    """The folder of study `name`, holding its study.toml and sweep files (a Path)."""
    for candidate in (_HERE / name, _HERE.parents[2] / "studies" / name):
        # the package's own copy, else the repository's folder (python/plumetrace/studies is
        # three levels below the repository's root)
        if (candidate / "study.toml").is_file():
            return candidate
    raise FileNotFoundError(f"plumetrace.studies: no study '{name}' (no study.toml in "
                            f"{_HERE / name}); the studies are {', '.join(names())}")


def sets(name):
    """The sweep files of study `name` in its study.toml's order, by the name each file
    gives itself (``{"A": Path(".../sets/A.toml"), ...}``)."""
    base = folder(name)
    files = _read_toml(base / "study.toml", "study file").get("sets", [])
    out = {}
    for rel in files:
        path = base / rel
        out[_read_toml(path, "sweep file").get("name", path.stem)] = path
    return out


def _read_toml(path, what):
    # read as every input is (plumetrace._files: a regular file, without blocking, bounded in
    # size); a mistake raises ValueError (BadPath) naming the file
    from .._files import read_toml

    return read_toml(path, what)


def _subpackage_path(package_path, name):
    """The __path__ of studies.NAME: its own folder, and the repository's when the package
    runs from the source tree (where the study's .py files stay in studies/NAME)."""
    own = Path(package_path[0])
    if not (own / "study.toml").is_file():
        repository = _HERE.parents[2] / "studies" / name
        if repository.is_dir():
            package_path.append(str(repository))
    return package_path

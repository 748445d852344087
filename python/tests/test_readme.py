"""The Python a newcomer copies, run as written: each ```python block of the README's "From
Python" section and of docs/python.md (the API the README points to), on its own, in an empty
folder (no repository files at hand, as after `pip install .`)."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import plumetrace_with_core  # noqa: E402

pt = plumetrace_with_core()

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"
PYTHON_DOC = ROOT / "docs" / "python.md"


def section_blocks(path, heading):
    """The ```python blocks of the section under `heading` (to the next heading of its level)."""
    text = path.read_text()
    start = text.index(f"\n{heading}\n")
    end = text.find("\n" + heading.split(" ")[0] + " ", start + 1)
    section = text[start:end if end >= 0 else len(text)]
    return re.findall(r"```python\n(.*?)```", section, re.S)


def python_blocks():
    """The README's "From Python", then every block of docs/python.md."""
    return (section_blocks(README, "## From Python")
            + re.findall(r"```python\n(.*?)```", PYTHON_DOC.read_text(), re.S))


def test_the_readme_has_the_first_script_and_the_doc_the_api_and_the_example_controller():
    readme = section_blocks(README, "## From Python")
    assert any('paper.sets["A"]' in b and "to_pandas()" in b for b in readme)
    blocks = python_blocks()
    assert len(blocks) >= 5
    assert any("pt.Scenario()" in b and "pt.probe(" in b for b in blocks)
    assert any("pt.register_controller(" in b for b in blocks)
    assert any("plumetrace.examples.python_surge_cast" in b for b in blocks)
    assert any("PlumeEnv(" in b for b in blocks)
    assert not any("from python_surge_cast" in b for b in blocks)


@pytest.mark.parametrize("index", range(len(python_blocks())))
def test_each_python_block_runs_as_written_from_an_empty_folder(index, tmp_path):
    code = python_blocks()[index]
    # the package under test, wherever it is (installed, or the build's folder), and no more
    import plumetrace

    env = dict(os.environ, PYTHONPATH=str(Path(plumetrace.__file__).resolve().parents[1]),
               MPLBACKEND="Agg")
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, f"block {index}:\n{code}\n{done.stderr}"
    if "to_pandas()" in code and "groupby" in code:
        # the first script prints the success rate per upwind angle: 9 values, rates in [0, 1]
        rates = [float(line.split()[-1]) for line in done.stdout.splitlines()
                 if re.fullmatch(r"\s*\d+(\.\d+)?\s+[01](\.\d+)?\s*", line)]
        assert len(rates) == 9 and all(0.0 <= r <= 1.0 for r in rates), done.stdout

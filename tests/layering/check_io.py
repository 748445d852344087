#!/usr/bin/env python3
"""Checks that every input file and output folder goes through the one helper of its language.

The guarantees of docs/reliability.md ("Inputs and outputs") hold for a surface by
construction only when its code cannot open a file another way: C++ reads input files with
read_regular_file or parse_toml_file and makes output folders with make_output_folder
(include/plumetrace/core/files.hpp); the Python package reads them with plumetrace._files and
makes folders with it. This fails (exit 1, one line per use) when a source outside the helpers
opens an input or makes a folder directly.

    check_io.py [ROOT]       check the tree at ROOT (default: the repository)
    check_io.py --self-test  check that the checker finds each forbidden use
"""
import re
import sys
import tempfile
from pathlib import Path

# C++: reading a file or making a folder other than through core/files.hpp
CPP_FORBIDDEN = [
    (re.compile(r"\bstd::ifstream\b"), "std::ifstream (use read_regular_file)"),
    (re.compile(r"\bfopen\s*\("), "fopen (use read_regular_file)"),
    (re.compile(r"\btoml::parse_file\b"), "toml::parse_file (use detail::parse_toml_file)"),
    (re.compile(r"\bcreate_director(y|ies)\s*\("),
     "create_directories (use make_output_folder)"),
]
# the helpers themselves, and what writes or reads its own files whole (stores through SQLite)
CPP_ALLOWED = {"src/core/files.cpp", "src/io/toml_input.cpp"}
CPP_DIRS = ["src", "cli", "studies"]

# Python: reading a TOML or text input, or making a folder, other than through plumetrace._files
PY_FORBIDDEN = [
    (re.compile(r"\btomllib\.loads?\b"), "tomllib (use plumetrace._files.read_toml)"),
    (re.compile(r"\.read_text\s*\("), "read_text (use plumetrace._files.read_input)"),
    (re.compile(r"\bopen\s*\([^)]*['\"]r?b?['\"]\s*\)"), "open for reading (use read_input)"),
    (re.compile(r"\.mkdir\s*\("), "mkdir (use plumetrace._files.output_folder)"),
    (re.compile(r"\bos\.makedirs\s*\("), "os.makedirs (use plumetrace._files.output_folder)"),
]
PY_ALLOWED = {"python/plumetrace/_files.py"}
PY_DIRS = ["python/plumetrace", "studies"]


def code_lines(text, comment):
    """The lines of `text` with their numbers, comments and docstring-free enough for a grep."""
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if stripped.startswith(comment):
            continue
        yield number, line.split(comment, 1)[0] if comment == "//" else line


def check(root: Path) -> list:
    problems = []
    for folder in CPP_DIRS:
        for path in sorted((root / folder).rglob("*")):
            rel = path.relative_to(root).as_posix()
            if path.suffix not in (".cpp", ".hpp") or rel in CPP_ALLOWED:
                continue
            for number, line in code_lines(path.read_text(errors="replace"), "//"):
                for pattern, what in CPP_FORBIDDEN:
                    if pattern.search(line):
                        problems.append(f"{rel}:{number}: {what}")
    for folder in PY_DIRS:
        for path in sorted((root / folder).rglob("*.py")):
            rel = path.relative_to(root).as_posix()
            if rel in PY_ALLOWED:
                continue
            for number, line in code_lines(path.read_text(errors="replace"), "#"):
                for pattern, what in PY_FORBIDDEN:
                    if pattern.search(line):
                        problems.append(f"{rel}:{number}: {what}")
    return problems


def self_test() -> int:
    cases = {
        "src/a.cpp": "std::ifstream in(path);\n",
        "cli/b.cpp": "std::filesystem::create_directories(out);\n",
        "studies/c.cpp": "auto t = toml::parse_file(p);\n",
        "python/plumetrace/d.py": "doc = tomllib.load(f)\n",
        "python/plumetrace/e.py": "out.mkdir(parents=True)\n",
        "python/plumetrace/f.py": "text = Path(p).read_text()\n",
        "python/plumetrace/g.py": "with open(p, 'rb') as f:\n",
    }
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        for rel, text in cases.items():
            (root / rel).parent.mkdir(parents=True, exist_ok=True)
            (root / rel).write_text(text)
        (root / "src/core").mkdir(parents=True)
        (root / "src/core/files.cpp").write_text("std::ifstream in(path);\n")
        (root / "src/ok.cpp").write_text("// std::ifstream in a comment\n")
        found = {p.split(":")[0] for p in check(root)}
    missed = set(cases) - found
    extra = found - set(cases)
    for rel in sorted(missed):
        print(f"self-test: the checker missed {rel}")
    for rel in sorted(extra):
        print(f"self-test: the checker flagged {rel}, which is allowed")
    return 1 if missed or extra else 0


def main(argv) -> int:
    if argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(argv[1]) if len(argv) > 1 else Path(__file__).resolve().parents[2]
    problems = check(root)
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} input or output folder(s) opened outside the helpers "
              "(docs/reliability.md, 'Inputs and outputs')")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

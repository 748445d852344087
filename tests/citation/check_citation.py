#!/usr/bin/env python3
"""Checks CITATION.cff: valid against the Citation File Format 1.2.0 schema (schema-1.2.0.json
beside this file, the official JSON Schema, CC-BY-4.0: NOTICE.md), its version the CMake
project's VERSION, its licence the one of LICENSE and pyproject.toml, and the paper it reproduces
among its references.

    check_citation.py [ROOT]      check ROOT/CITATION.cff (default: the repository)
    check_citation.py --self-test check that the checker refuses broken files

Needs PyYAML and jsonschema (Debian: python3-yaml, python3-jsonschema; scripts/setup.sh --test).
"""
import json
import re
import sys
import tempfile
from pathlib import Path

import jsonschema
import yaml

HERE = Path(__file__).resolve().parent
SCHEMA = HERE / "schema-1.2.0.json"
PAPER = "Simulation Experiments with Bio-Inspired Algorithms for Odor Source Localization in"


class _Loader(yaml.SafeLoader):
    """YAML as CFF reads it: a date stays the text it was written as. The schema asks for that
    ("cast YAML 'date' objects to string objects when validating")."""


_Loader.yaml_implicit_resolvers = {
    first: [(tag, rx) for tag, rx in resolvers if tag != "tag:yaml.org,2002:timestamp"]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}


def project_version(root: Path) -> str:
    match = re.search(r"project\(plumetrace\s+VERSION\s+([0-9][0-9.]*)",
                      (root / "CMakeLists.txt").read_text())
    if not match:
        raise SystemExit(f"{root / 'CMakeLists.txt'}: no 'project(plumetrace VERSION x.y.z'")
    return match.group(1)


def project_licence(root: Path) -> str:
    match = re.search(r'^license\s*=\s*\{\s*text\s*=\s*"([^"]+)"', (root / "pyproject.toml").read_text(),
                      re.M)
    if not match:
        raise SystemExit(f"{root / 'pyproject.toml'}: no 'license = {{text = \"...\"}}'")
    return match.group(1)


def problems(root: Path) -> list:
    """Every problem of ROOT/CITATION.cff, one line each; empty when it is valid."""
    path = root / "CITATION.cff"
    try:
        doc = yaml.load(path.read_text(encoding="utf-8"), Loader=_Loader)
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as e:
        return [f"{path}: cannot be read as YAML: {e}"]
    schema = json.loads(SCHEMA.read_text())
    validator = jsonschema.Draft7Validator(schema, format_checker=jsonschema.FormatChecker())
    out = [f"{path}: {'/'.join(map(str, e.absolute_path)) or '(top)'}: {e.message}"
           for e in sorted(validator.iter_errors(doc), key=lambda e: list(map(str, e.path)))]
    if not isinstance(doc, dict):
        return out or [f"{path}: not a mapping"]
    version = project_version(root)
    if str(doc.get("version")) != version:
        out.append(f"{path}: version {doc.get('version')!r} is not the project's {version} "
                   "(CMakeLists.txt)")
    licence = project_licence(root)
    if doc.get("license") != licence:
        out.append(f"{path}: license {doc.get('license')!r} is not pyproject.toml's {licence!r}")
    first_line = (root / "LICENSE").read_text().splitlines()[0]
    if licence == "BSD-3-Clause" and first_line != "BSD 3-Clause License":
        out.append(f"{root / 'LICENSE'}: starts '{first_line}', not the BSD 3-Clause licence")
    papers = [r for r in doc.get("references") or [] if isinstance(r, dict)
              and " ".join(str(r.get("title", "")).split()).startswith(PAPER)]
    if not papers:
        out.append(f"{path}: no reference titled '{PAPER} ...' (Lochmatter & Martinoli 2008)")
    for r in papers:
        names = [a.get("family-names") for a in r.get("authors", []) if isinstance(a, dict)]
        if names != ["Lochmatter", "Martinoli"] or r.get("year") != 2008:
            out.append(f"{path}: the paper's reference names {names}, {r.get('year')}; "
                       "want Lochmatter, Martinoli, 2008")
    return out


def self_test() -> int:
    """Broken copies of the repository's file must each be refused for their fault."""
    root = HERE.parents[1]
    good = (root / "CITATION.cff").read_text(encoding="utf-8")
    cases = {
        "no authors": (re.sub(r"(?ms)^authors:\n(  - .*?\n)+", "", good, count=1), "authors"),
        "an unknown key": (good + "colour: blue\n", "colour"),
        "a bad date": (good.replace('date-released: "', 'date-released: "20'), "date-released"),
        "an old version": (good.replace("\nversion: ", "\nversion: 0.0.9-was-"), "version"),
        "a reference without a type": (good.replace("  - type: conference-paper\n", "  -\n"),
                                       "type"),
        "another licence": (good.replace("license: BSD-3-Clause", "license: MIT"), "license"),
        "not the paper": (good.replace("Simulation Experiments", "Other Experiments"),
                          "Lochmatter"),
    }
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for name in ("CMakeLists.txt", "pyproject.toml", "LICENSE"):
            (tmp / name).write_text((root / name).read_text())
        (tmp / "CITATION.cff").write_text(good, encoding="utf-8")
        if problems(tmp):
            print(f"self-test: the repository's own file is refused: {problems(tmp)}")
            failed += 1
        # an unquoted date is a YAML date: it must be read as its text, as the schema says
        (tmp / "CITATION.cff").write_text(good.replace('date-released: "2026-11-23"',
                                                       "date-released: 2026-11-23"))
        if problems(tmp):
            print(f"self-test: an unquoted date is refused: {problems(tmp)}")
            failed += 1
        for name, (text, word) in cases.items():
            if text == good:
                print(f"self-test: case '{name}' changed nothing")
                failed += 1
                continue
            (tmp / "CITATION.cff").write_text(text, encoding="utf-8")
            found = problems(tmp)
            if not any(word in p for p in found):
                print(f"self-test: {name} not found (problems: {found})")
                failed += 1
    print("check_citation self-test:", "FAILED" if failed else f"{len(cases) + 2} cases OK")
    return 1 if failed else 0


def main(argv: list) -> int:
    if argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(argv[1]) if len(argv) > 1 else HERE.parents[1]
    found = problems(root)
    for p in found:
        print(p)
    if not found:
        print(f"CITATION.cff: valid CFF 1.2.0, version {project_version(root)}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""Checks the include graph against the layer table of docs/architecture.md.

Fails (exit 1, one line per problem) when a file includes a module of a layer its own layer may
not use, when a controller includes more than the controller interface, the measurements and other
controllers (which obey the same rule),
when an include names no file, or when modules include each other (any cycle). A module is a
header and its source (include/plumetrace/env/wind.hpp and src/env/wind.cpp are env/wind).

    check_layers.py [ROOT]      check the tree at ROOT (default: the repository)
    check_layers.py --self-test check that the checker finds a back edge, a cycle and a
                                controller that sees the environment
"""
import re
import sys
import tempfile
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
TABLE_START = "<!-- layers: read by tests/layering/check_layers.py -->"
TABLE_END = "<!-- /layers -->"
# what a controller may include besides the core layer (docs/architecture.md, "Controllers")
CONTROLLER_MAY_SEE = {"agent/controller", "agent/measurement"}


def read_layers(doc: Path) -> dict:
    """The table between the markers: layer -> the layers it may include (itself included)."""
    text = doc.read_text()
    if TABLE_START not in text or TABLE_END not in text:
        raise SystemExit(f"{doc}: no layer table between '{TABLE_START}' and '{TABLE_END}'")
    rows = text.split(TABLE_START, 1)[1].split(TABLE_END, 1)[0].strip().splitlines()[2:]
    layers = {}
    for row in rows:
        cells = [c.strip().strip("`") for c in row.strip().strip("|").split("|")]
        if len(cells) < 3:
            raise SystemExit(f"{doc}: layer row '{row}' has fewer than three cells")
        name, may = cells[0], cells[2]
        allowed = {x.strip().strip("`") for x in may.split(",") if x.strip() not in ("", "-")}
        layers[name] = allowed | {name}
    return layers


def sources(root: Path):
    """(file, module, layer) for every C++ file of the library, the studies, the CLI, bindings."""
    for f in sorted((root / "include/plumetrace").rglob("*.hpp")):
        rel = f.relative_to(root / "include/plumetrace").with_suffix("")
        yield f, str(rel), rel.parts[0]
    for f in sorted((root / "src").rglob("*.[ch]pp")):
        rel = f.relative_to(root / "src").with_suffix("")
        yield f, str(rel), rel.parts[0]
    for f in sorted((root / "studies").rglob("*.[ch]pp")):
        rel = f.relative_to(root / "studies").with_suffix("")
        yield f, "studies/" + str(rel), "studies"
    for f in sorted((root / "cli").rglob("*.[ch]pp")):
        yield f, "cli/" + str(f.relative_to(root / "cli").with_suffix("")), "cli"
    bindings = root / "python/bindings.cpp"
    if bindings.exists():
        yield bindings, "python/bindings", "python"


def resolve(root: Path, f: Path, name: str):
    """The module an include names, or None for a system or generated header."""
    if name.startswith("plumetrace/"):
        rel = name[len("plumetrace/"):]
        if (root / "include/plumetrace" / rel).exists():
            return str(Path(rel).with_suffix(""))
        return None if rel in ("version.hpp", "paths.hpp") else "?" + name
    here = f.parent / name
    if here.exists():
        for base, prefix in ((root / "src", ""), (root / "studies", "studies/"),
                             (root / "cli", "cli/")):
            try:
                return prefix + str(here.resolve().relative_to(base.resolve()).with_suffix(""))
            except ValueError:
                pass
    if (root / "studies" / name).exists():
        return "studies/" + str(Path(name).with_suffix(""))
    # the CLI's own headers are found from its folder (cli/commands/x.cpp: "errors.hpp")
    if (root / "cli" / name).exists() and (root / "cli") in f.parents:
        return "cli/" + str(Path(name).with_suffix(""))
    return None if "/" not in name and not name.endswith(".hpp") else "?" + name


def layer_of(module: str) -> str:
    return module.split("/")[0]


def check(root: Path) -> list:
    layers = read_layers(root / "docs/architecture.md")
    problems, edges = [], {}
    for f, module, layer in sources(root):
        where = f.relative_to(root)
        if layer not in layers:
            problems.append(f"{where}: layer '{layer}' is not in the table of docs/architecture.md")
            continue
        for name in INCLUDE.findall(f.read_text()):
            target = resolve(root, f, name)
            if target is None:
                continue
            if target.startswith("?"):
                problems.append(f'{where}: #include "{name}" names no file')
                continue
            if target != module:
                edges.setdefault(module, set()).add(target)
            to = layer_of(target)
            if to not in layers[layer]:
                problems.append(f'{where}: layer {layer} includes "{name}" of layer {to} '
                                f"(it may include: {', '.join(sorted(layers[layer]))})")
            # why: another controller sees no more than the rule lets it (the particle filter
            # rides on surge-spiral)
            if module.startswith("agent/controllers/") and to != "core" and \
                    target not in CONTROLLER_MAY_SEE and \
                    not target.startswith("agent/controllers/"):
                problems.append(f'{where}: a controller includes "{name}"; controllers see only other controllers, '
                                f"{', '.join(sorted(CONTROLLER_MAY_SEE))} and the core")
    problems += [f"modules include each other: {' -> '.join(c)}" for c in cycles(edges)]
    return problems


def cycles(edges: dict) -> list:
    """Each strongly connected component of more than one module, as a closed path."""
    index, low, stack, on, out, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp) + [sorted(comp)[0]])

    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def self_test() -> int:
    """Builds small trees with known faults; each must be found, and a clean one must pass."""
    table = (f"{TABLE_START}\n| layer | folder | may include |\n|---|---|---|\n"
             "| core | core | - |\n| env | env | core |\n| agent | agent | core, env |\n"
             f"{TABLE_END}\n")

    def tree(files: dict) -> list:
        with tempfile.TemporaryDirectory() as d:
            root = Path(d)
            (root / "docs").mkdir()
            (root / "docs/architecture.md").write_text(table)
            for path, text in files.items():
                (root / path).parent.mkdir(parents=True, exist_ok=True)
                (root / path).write_text(text)
            return check(root)

    inc = lambda m: f'#include "plumetrace/{m}.hpp"\n'
    clean = {"include/plumetrace/core/a.hpp": "", "include/plumetrace/env/w.hpp": inc("core/a"),
             "src/env/w.cpp": inc("env/w"), "include/plumetrace/agent/controller.hpp": "",
             "include/plumetrace/agent/controllers/c.hpp": inc("agent/controller")}
    cases = {
        "back edge": dict(clean, **{"include/plumetrace/core/b.hpp": inc("env/w")}),
        "cycle": dict(clean, **{"include/plumetrace/env/v.hpp": inc("env/w"),
                                "src/env/w.cpp": inc("env/v")}),
        "controller sees the environment": dict(
            clean, **{"src/agent/controllers/c.cpp": inc("env/w")}),
        "missing header": dict(clean, **{"src/env/x.cpp": inc("env/nothing")}),
    }
    failed = 0
    if tree(clean):
        print("self-test: a clean tree was refused:", tree(clean))
        failed += 1
    for name, files in cases.items():
        found = tree(files)
        print(f"self-test: {name}: {'found' if found else 'MISSED'}: {found}")
        failed += not found
    return 1 if failed else 0


def main() -> int:
    if sys.argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2]
    problems = check(root)
    for p in problems:
        print(p)
    if not problems:
        print("layering: every include follows docs/architecture.md, and no module cycle")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Checks the relative links of README.md, CHANGELOG.md and docs/*.md: each names a file or
folder of the repository, and each #anchor a heading of the page it points to, under GitHub's
rules (lowercase; everything but letters, digits, spaces, '-' and '_' dropped; spaces become '-';
a repeated heading gets -1, -2, ...). Links in code blocks and code spans are text, not links;
web addresses are not followed.

    check_links.py [ROOT]      check the pages under ROOT (default: the repository)
    check_links.py --self-test check that the checker finds a missing file, a missing anchor and
                               a broken link to a page's own heading, and follows GitHub's slugs
"""
import re
import sys
import tempfile
from pathlib import Path

FENCE = re.compile(r"^ {0,3}(```|~~~)")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
# [text](target) and ![alt](target); the text may hold one level of brackets, the target an
# optional "title"
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+\"[^\"]*\")?\s*\)")
SCHEME = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def pages(root: Path):
    """The Markdown pages whose links are checked."""
    for name in ("README.md", "CHANGELOG.md"):
        if (root / name).is_file():
            yield root / name
    yield from sorted((root / "docs").glob("*.md"))


def prose_lines(text: str):
    """(line number, line) outside fenced code blocks."""
    fenced = False
    for number, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield number, line


def slug(heading: str) -> str:
    """GitHub's anchor of a heading's text (before de-duplication)."""
    text = CODE_SPAN.sub(lambda m: m.group(2), heading)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)   # a link shows its text
    text = re.sub(r"<[^>]+>", "", text)                      # inline HTML
    return re.sub(r"[^\w\- ]", "", text.lower()).replace(" ", "-")


def anchors(path: Path) -> set:
    """Every anchor GitHub gives the headings of a page."""
    seen, out = {}, set()
    for _, line in prose_lines(path.read_text(encoding="utf-8")):
        match = HEADING.match(line)
        if not match:
            continue
        base = slug(match.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def problems(root: Path) -> list:
    """One line per broken link: page:line: target: why."""
    out, cache = [], {}
    for page in pages(root):
        for number, line in prose_lines(page.read_text(encoding="utf-8")):
            for match in LINK.finditer(CODE_SPAN.sub("", line)):
                target = match.group(1)
                if not target or SCHEME.match(target):
                    continue
                where, _, anchor = target.partition("#")
                dest = (page.parent / where).resolve() if where else page
                name = f"{page.relative_to(root)}:{number}: {target}"
                if not dest.exists():
                    out.append(f"{name}: no such file")
                    continue
                if root.resolve() not in dest.parents and dest != root.resolve():
                    out.append(f"{name}: outside the repository")
                    continue
                if anchor and dest.suffix == ".md":
                    if dest not in cache:
                        cache[dest] = anchors(dest)
                    if anchor not in cache[dest]:
                        out.append(f"{name}: no heading with anchor '#{anchor}' in "
                                   f"{dest.relative_to(root.resolve())}")
    return out


def self_test() -> int:
    """A small tree with one good link of each kind and one broken link of each kind."""
    cases = {
        "slugs": [
            (slug("`plumetrace run`"), "plumetrace-run"),
            (slug("3.1 Meandering wind (Farrell et al. 2002)"), "31-meandering-wind-farrell-et-al-2002"),
            (slug("4.4a Farrell et al.'s relative dispersion (`plume.dispersion = \"farrell\"`)"),
             "44a-farrell-et-als-relative-dispersion-plumedispersion--farrell"),
            (slug("10. Where the spiral starts (`surge_spiral.start_radius`)"),
             "10-where-the-spiral-starts-surge_spiralstart_radius"),
            (slug("The unit of σ_a"), "the-unit-of-σ_a"),
        ],
    }
    failed = 0
    for got, want in cases["slugs"]:
        if got != want:
            print(f"self-test: slug {got!r}, want {want!r}")
            failed += 1
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "docs").mkdir()
        (root / "docs" / "a.md").write_text(
            "# A\n\n## Same\n\n## Same\n\n## `code` heading\n\n```\n## not a heading\n```\n")
        (root / "README.md").write_text(
            "# R\n\n[good](docs/a.md) [good](docs/a.md#same-1) [good](docs/a.md#code-heading)\n"
            "[good](#r) [web](https://example.org/x#y) `[in code](nowhere.md)`\n"
            "```\n[in a block](nowhere.md)\n```\n"
            "[missing file](docs/b.md) [missing anchor](docs/a.md#same-2)\n"
            "[own anchor](#nope) [fenced heading](docs/a.md#not-a-heading)\n"
            "[outside](../elsewhere.md)\n")
        found = problems(root)
        for want in ("docs/b.md: no such file", "docs/a.md#same-2: no heading",
                     "#nope: no heading", "docs/a.md#not-a-heading: no heading",
                     "../elsewhere.md: "):
            if not any(want in p for p in found):
                print(f"self-test: '{want}' not found in {found}")
                failed += 1
        if len(found) != 5:
            print(f"self-test: {len(found)} problems, want 5: {found}")
            failed += 1
    print("check_links self-test:", "FAILED" if failed else "OK")
    return 1 if failed else 0


def main(argv: list) -> int:
    if argv[1:] == ["--self-test"]:
        return self_test()
    root = Path(argv[1] if len(argv) > 1 else Path(__file__).resolve().parents[2])
    found = problems(root)
    for p in found:
        print(p)
    if not found:
        checked = sum(1 for _ in pages(root))
        print(f"check_links: every relative link of {checked} pages resolves")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

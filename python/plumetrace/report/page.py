"""The report as a document (Cell, Para, Table, Fig, Pre, Bullets, Section), rendered to HTML
and Markdown from the same sections, and written to report.html and report.md."""

from __future__ import annotations

import base64
import html
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Optional, Sequence, Union

from .._files import BadPath, exit_status, output_folder
from .data import DASH, write_whole

@dataclass
class Cell:
    text: str
    cls: Optional[str] = None
    title: Optional[str] = None
    num: bool = False


CellLike = Union[str, Cell]


@dataclass
class Para:
    spans: list  # str, ("code" | "b", text) or ("a", text, "#anchor")


@dataclass
class Table:
    header: Optional[list]  # None: no header row (Markdown still needs one; it stays empty)
    rows: list  # list of list of CellLike
    row_classes: list = field(default_factory=list)
    caption: Optional[str] = None


@dataclass
class Fig:
    path: Path  # absolute
    rel: str  # relative to the output folder, with forward slashes
    caption: str
    alt: str


@dataclass
class Pre:
    text: str
    lang: str = ""


@dataclass
class Bullets:
    items: list  # each a list of spans


@dataclass
class Section:
    anchor: str
    title: str
    blocks: list
    level: int = 2


def _cell(c: CellLike) -> Cell:
    return c if isinstance(c, Cell) else Cell(str(c))


CSS = """
body { font-family: -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif;
       color: #222; max-width: 1100px; margin: 1.5em auto; padding: 0 1.2em; line-height: 1.45; }
h1 { font-size: 1.7em; margin-bottom: 0.2em; }
h2 { border-bottom: 2px solid #ddd; padding-bottom: 0.15em; margin-top: 2em; }
h3 { margin-top: 1.6em; }
table { border-collapse: collapse; margin: 0.6em 0 1.2em; font-size: 0.88em; }
th, td { border: 1px solid #bbb; padding: 0.25em 0.55em; text-align: left; vertical-align: top; }
th { background: #eef1f5; }
td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.mono, code { font-family: "SFMono-Regular", Consolas, "Liberation Mono", monospace;
                font-size: 0.92em; }
tr.fixed td { background: #eef4fb; font-weight: 600; }
tr.incomplete td { color: #a33; }
td.holds { background: #c8e6c9; } td.fails { background: #ffcdd2; }
td.unclear { background: #ffe0a3; } td.other { background: #e0e0e0; }
td.verdict { font-weight: 600; white-space: nowrap; }
td.cell { text-align: center; min-width: 1.6em; }
figure { margin: 0.8em 0 1.2em; }
figure img { max-width: 100%; height: auto; border: 1px solid #e3e3e3; }
figcaption { font-size: 0.88em; color: #444; margin-top: 0.3em; }
pre { background: #f6f8fa; border: 1px solid #ddd; padding: 0.8em; overflow: auto;
      font-size: 0.82em; line-height: 1.35; }
nav.toc { background: #f7f7f7; border: 1px solid #e2e2e2; padding: 0.4em 1em;
          display: inline-block; }
nav.toc ol { margin: 0.3em 0; padding-left: 1.4em; }
td.key { background: #eef1f5; font-weight: 600; white-space: nowrap; }
""".strip()


def _h(text: Any) -> str:
    return html.escape(str(text), quote=True)


def _html_spans(spans: Sequence) -> str:
    out = []
    for s in spans:
        if isinstance(s, tuple) and s[0] == "a":
            out.append(f'<a href="{_h(s[2])}">{_h(s[1])}</a>')
        elif isinstance(s, tuple):
            kind, text = s
            out.append(f"<code>{_h(text)}</code>" if kind == "code" else f"<b>{_h(text)}</b>")
        else:
            out.append(_h(s))
    return "".join(out)


def _html_cell_text(text: str) -> str:
    return "<br>".join(_h(line) for line in text.split("\n"))


def _html_block(b: Any) -> str:
    if isinstance(b, Para):
        return f"<p>{_html_spans(b.spans)}</p>"
    if isinstance(b, Bullets):
        items = "".join(f"<li>{_html_spans(item)}</li>" for item in b.items)
        return f"<ul>{items}</ul>"
    if isinstance(b, Pre):
        return f"<pre>{_h(b.text)}</pre>"
    if isinstance(b, Fig):
        data = base64.b64encode(b.path.read_bytes()).decode("ascii")
        return (f'<figure><img src="data:image/png;base64,{data}" alt="{_h(b.alt)}">'
                f"<figcaption>{_h(b.caption)}</figcaption></figure>")
    if isinstance(b, Table):
        parts = ["<table>"]
        if b.caption:
            parts.append(f"<caption>{_h(b.caption)}</caption>")
        if b.header:
            parts.append("<thead><tr>" + "".join(f"<th>{_h(c)}</th>" for c in b.header)
                         + "</tr></thead>")
        parts.append("<tbody>")
        for i, row in enumerate(b.rows):
            rcls = b.row_classes[i] if i < len(b.row_classes) else None
            parts.append(f'<tr class="{_h(rcls)}">' if rcls else "<tr>")
            for c in map(_cell, row):
                classes = " ".join(x for x in (c.cls, "num" if c.num else None) if x)
                attrs = (f' class="{_h(classes)}"' if classes else "") + (
                    f' title="{_h(c.title)}"' if c.title else "")
                parts.append(f"<td{attrs}>{_html_cell_text(c.text)}</td>")
            parts.append("</tr>")
        parts.append("</tbody></table>")
        return "".join(parts)
    raise TypeError(type(b))


def render_html(title: str, intro: list, sections: list) -> str:
    toc = "".join(f'<li><a href="#{_h(s.anchor)}">{_h(s.title)}</a></li>'
                  for s in sections if s.level == 2)
    body = [f"<h1>{_h(title)}</h1>"]
    body += [_html_block(b) for b in intro]
    body.append(f'<nav class="toc"><b>Contents</b><ol>{toc}</ol></nav>')
    for s in sections:
        body.append(f'<h{s.level} id="{_h(s.anchor)}">{_h(s.title)}</h{s.level}>')
        body += [_html_block(b) for b in s.blocks]
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
            f"<title>{_h(title)}</title>\n<style>\n{CSS}\n</style>\n</head>\n<body>\n"
            + "\n".join(body) + "\n</body>\n</html>\n")


# why: "[" and "_" are left alone (no link definitions here; GFM ignores intraword "_"), and ">"
# matters only at the start of a line, so raw report.md stays readable.
_MD_SPECIAL = str.maketrans({c: "\\" + c for c in "\\`*<|"})


def _md(text: Any) -> str:
    out = str(text).translate(_MD_SPECIAL)
    return "\\" + out if out[:1] in (">", "#", "+", "-") else out


def _md_spans(spans: Sequence) -> str:
    out = []
    for s in spans:
        if isinstance(s, tuple) and s[0] == "a":
            out.append(f"[{_md(s[1])}]({s[2]})")
        elif isinstance(s, tuple):
            kind, text = s
            if kind == "code":
                fence = "``" if "`" in text else "`"
                out.append(f"{fence}{text}{fence}")
            else:
                out.append(f"**{_md(text)}**")
        else:
            out.append(_md(s))
    return "".join(out)


def _md_block(b: Any) -> str:
    if isinstance(b, Para):
        return _md_spans(b.spans)
    if isinstance(b, Bullets):
        return "\n".join(f"- {_md_spans(item)}" for item in b.items)
    if isinstance(b, Pre):
        longest = max((len(run) for run in b.text.split("\n") if set(run) == {"`"}), default=0)
        fence = "`" * max(3, longest + 1)
        return f"{fence}{b.lang}\n{b.text.rstrip()}\n{fence}"
    if isinstance(b, Fig):
        alt = _md(b.alt).replace("[", "\\[").replace("]", "\\]")
        return f"![{alt}]({b.rel})\n\n*{_md(b.caption)}*"
    if isinstance(b, Table):
        lines = []
        if b.caption:
            lines += [_md(b.caption), ""]
        width = len(b.header) if b.header else max((len(r) for r in b.rows), default=1)
        header = b.header or [""] * width
        lines.append("| " + " | ".join(_md(h) for h in header) + " |")
        lines.append("|" + "|".join("---:" if _cell(c).num else "---"
                                    for c in (b.rows[0] if b.rows else header)) + "|")
        for i, row in enumerate(b.rows):
            strong = i < len(b.row_classes) and b.row_classes[i] == "fixed"
            cells = []
            for c in map(_cell, row):
                text = "<br>".join(_md(line) for line in c.text.split("\n"))
                cells.append(f"**{text}**" if strong and text and text != DASH else text)
            lines.append("| " + " | ".join(cells) + " |")
        return "\n".join(lines)
    raise TypeError(type(b))


def render_markdown(title: str, intro: list, sections: list) -> str:
    out = [f"# {_md(title)}", ""]
    for b in intro:
        out += [_md_block(b), ""]
    out.append("Contents:")
    out += [f"{i}. [{_md(s.title)}](#{s.anchor})"
            for i, s in enumerate((s for s in sections if s.level == 2), 1)]
    out.append("")
    for s in sections:
        out += [f'<a id="{s.anchor}"></a>', "", f"{'#' * s.level} {_md(s.title)}", ""]
        for b in s.blocks:
            out += [_md_block(b), ""]
    return "\n".join(out).rstrip() + "\n"


def _fig(out_dir: Path, path: Path, caption: str, alt: str) -> Fig:
    return Fig(path=path, rel=path.relative_to(out_dir).as_posix(), caption=caption, alt=alt)


# The repository's root: this file is python/plumetrace/report/page.py there, or a copy in
# BUILD/python/plumetrace/report/ of a build folder inside it.
REPO_ROOT = next((p for p in Path(__file__).resolve().parents[2:5]
                  if (p / "docs").is_dir() and (p / "studies").is_dir()),
                 Path(__file__).resolve().parents[3])

# The project's documents the reports cite: the package's copy (a build or an installed package
# ships docs/*.md, cmake/python_package.cmake), else the repository's (the source tree).
DOCS_ROOT = next((d for d in (Path(__file__).resolve().parents[1] / "docs", REPO_ROOT / "docs")
                  if d.is_dir()), REPO_ROOT / "docs")

def report_command(out_dir: Union[str, Path]) -> str:
    """The command that redraws a report from its folder's summary.json, as the README gives it
    (the package installed: README, "From Python")."""
    return f"python3 -m plumetrace.report {shlex.quote(str(out_dir))}"


def _doc_link(out_dir: Path, rel: str) -> tuple:
    """A link to one of the project's documents (`rel`: "docs/model.md") as the report's folder
    holds it: write_pages copies each linked page into out_dir/docs/ (bundle_docs), so that the
    link works wherever the folder is moved or copied. Plain text where the page is not found."""
    if not (DOCS_ROOT / Path(rel).relative_to("docs")).is_file():
        return ("code", rel)
    return ("a", rel, rel)


# a Markdown link's target: ](target) or ](target#anchor)
_MD_LINK = re.compile(r"\]\(([^)#\s]+)(?:#[^)\s]*)?\)")


def bundle_docs(out_dir: Path, hrefs: Iterable[str]) -> list:
    """Copies the documents `hrefs` ("docs/NAME.md") link, with every document of docs/ those
    link in turn, into out_dir/docs/; returns the paths written."""
    todo = [h[len("docs/"):] for h in hrefs if h.startswith("docs/")]
    done: set = set()
    written = []
    while todo:
        name = todo.pop()
        source = (DOCS_ROOT / name).resolve()
        if name in done or not source.is_file() or not source.is_relative_to(DOCS_ROOT.resolve()):
            continue
        done.add(name)
        target = out_dir / "docs" / name
        output_folder(target.parent, "the report's docs")
        data = source.read_bytes()
        written.append(write_whole(target, data))
        if name.endswith(".md"):
            base = Path(name).parent
            todo += [(base / m).as_posix() for m in _MD_LINK.findall(data.decode("utf-8"))
                     if "://" not in m and not m.startswith("/")]
    return written


def _links(blocks: Sequence) -> list:
    """The targets of the links in `blocks` (paragraphs and bullet lists)."""
    spans = []
    for b in blocks:
        if isinstance(b, Para):
            spans += b.spans
        elif isinstance(b, Bullets):
            spans += [s for item in b.items for s in item]
    return [s[2] for s in spans if isinstance(s, tuple) and s[0] == "a"]


def write_pages(out_dir: Path, title: str, intro: list, sections: list) -> list:
    """Writes report.html and report.md, each whole, and the documents they link into
    out_dir/docs/ (bundle_docs); returns the paths of the two pages."""
    links = _links(intro) + [h for s in sections for h in _links(s.blocks)]
    bundle_docs(Path(out_dir), links)
    html_path = write_whole(out_dir / "report.html", render_html(title, intro, sections))
    md_path = write_whole(out_dir / "report.md", render_markdown(title, intro, sections))
    return [html_path, md_path]


def study_report_main(argv: Optional[Sequence[str]], build, errors: tuple, usage: str,
                      name: str) -> int:
    """The command line of a study's report (`plumetrace study` runs it with OUT_DIR):
    `build(OUT_DIR)` writes the pages, each printed; exit 0, 2 for bad input (no OUT_DIR, one of
    `errors`, a malformed file) or 3 when a file cannot be read or written (exit_status)."""
    import sys

    args = sys.argv[1:] if argv is None else list(argv)
    if len(args) != 1:
        print(f"usage: {usage} OUT_DIR", file=sys.stderr)
        return 2
    try:
        for p in build(args[0]):
            print(f"wrote {p}")
    except (*errors, BadPath, OSError) as e:
        print(f"{name}: error: {e}", file=sys.stderr)
        return exit_status(e)
    return 0

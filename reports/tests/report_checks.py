"""Shared helpers for the report tests: run the generator, check the HTML."""
from __future__ import annotations

import html.parser
import os
import subprocess
import sys
from pathlib import Path

REPORTS = Path(__file__).resolve().parent.parent
GENERATE = REPORTS / "generate.py"
FIXTURES = REPORTS / "tests" / "fixtures"
VOID = {"meta", "img", "br", "hr", "link", "input", "col", "area", "base", "wbr", "source"}


def run_generator(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run([sys.executable, str(GENERATE), *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)


class HtmlCheck(html.parser.HTMLParser):
    """Tag balance and no external resources (every src is data:, every href an anchor)."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.errors: list[str] = []
        self.ids: set[str] = set()
        self.images = 0
        self.rows: list[tuple[str, list[str]]] = []  # (tr class, cell texts)
        self._row = None
        self._cell = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        for key in ("src", "href"):
            v = a.get(key)
            if v is not None and not (v.startswith("data:") if key == "src" else v.startswith("#")):
                self.errors.append(f"external resource <{tag} {key}={v[:60]}>")
        if tag in ("script", "link", "iframe", "object"):
            self.errors.append(f"<{tag}> not allowed in a self-contained report")
        if tag == "img":
            self.images += 1
        if tag == "tr":
            self._row = (a.get("class", ""), [])
        if tag in ("td", "th"):
            self._cell = []
        if tag not in VOID:
            self.stack.append(tag)

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else 'nothing'}> at {self.getpos()}")
            return
        self.stack.pop()
        if tag in ("td", "th") and self._row is not None and self._cell is not None:
            self._row[1].append("".join(self._cell).strip())
            self._cell = None
        if tag == "tr" and self._row is not None:
            self.rows.append(self._row)
            self._row = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def check_html(path: Path) -> HtmlCheck:
    text = path.read_text(encoding="utf-8")
    parser = HtmlCheck()
    parser.feed(text)
    parser.close()
    if not text.startswith("<!DOCTYPE html>"):
        parser.errors.append("no <!DOCTYPE html>")
    if parser.stack:
        parser.errors.append(f"unclosed tags at end: {parser.stack}")
    return parser


def summary_rows(path: Path) -> dict[str, dict[str, str]]:
    import csv
    with path.open(newline="", encoding="utf-8") as f:
        return {r["id"]: r for r in csv.DictReader(f)}

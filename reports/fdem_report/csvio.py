"""Strict CSV reading: every file the report reads has a declared header, and a
file that does not match it stops the report with the file and line named.

A wrong header, a cell that is not a number where a number is due, or a row
with the wrong number of cells is an InputError (exit code 2). Lines starting
with '#' and blank lines are skipped; each remaining line is one record (quoted
fields may hold commas but not newlines, so line numbers stay exact)."""
from __future__ import annotations

import csv
import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path


class InputError(Exception):
    """A malformed input file; the message names the file and, where known, the line."""

    def __init__(self, path: Path | str, line: int | None, reason: str):
        self.path = str(path)
        self.line = line
        self.reason = reason
        where = f"{self.path}:{line}" if line is not None else self.path
        super().__init__(f"{where}: {reason}")


@dataclass(frozen=True)
class Column:
    name: str
    kind: str = "num"  # "num": float (empty cell = missing, NaN); "str": text


@dataclass(frozen=True)
class Schema:
    """Header contract of one file kind. Required columns must all be present;
    optional ones may be; extra columns must match `extra_pattern` (numeric)."""

    title: str
    required: tuple[Column, ...]
    optional: tuple[Column, ...] = ()
    extra_pattern: str | None = None
    exact_order: bool = False  # the header must start with `required`, in order (optional ones after)

    def column(self, name: str) -> Column | None:
        for c in self.required + self.optional:
            if c.name == name:
                return c
        if self.extra_pattern and re.fullmatch(self.extra_pattern, name):
            return Column(name, "num")
        return None


@dataclass
class Table:
    path: Path
    columns: list[str]
    rows: list[dict[str, object]] = field(default_factory=list)
    lines: list[int] = field(default_factory=list)  # source line of each row

    def has(self, name: str) -> bool:
        return name in self.columns

    def col(self, name: str) -> list:
        return [r.get(name) for r in self.rows]

    def num(self, name: str):
        import numpy as np
        return np.array([math.nan if r.get(name) is None else r[name] for r in self.rows], dtype=float)


def _records(path: Path):
    """(line number, fields) for each non-comment, non-blank line."""
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError as e:
        raise InputError(path, None, f"not UTF-8 text ({e})") from None
    for lineno, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            fields = next(csv.reader([line], strict=True))
        except csv.Error as e:
            raise InputError(path, lineno, f"CSV syntax: {e}") from None
        yield lineno, [f.strip() for f in fields]


def parse_number(path: Path, lineno: int, column: str, text: str, allow_empty: bool) -> float | None:
    if text == "":
        if allow_empty:
            return None
        raise InputError(path, lineno, f"column '{column}' is empty; a number is required")
    try:
        return float(text)
    except ValueError:
        raise InputError(path, lineno, f"column '{column}': '{text}' is not a number") from None


def read_table(path: Path, schema: Schema, allow_empty_numbers: bool = True) -> Table:
    records = _records(path)
    try:
        header_line, header = next(records)
    except StopIteration:
        raise InputError(path, None, f"empty file; expected header for {schema.title}: "
                         + ",".join(c.name for c in schema.required)) from None
    expected = [c.name for c in schema.required]
    if schema.exact_order and header[:len(expected)] != expected:
        raise InputError(path, header_line, f"wrong header {','.join(header)}; expected {','.join(expected)}"
                         + (f" (then optionally {','.join(c.name for c in schema.optional)})" if schema.optional else ""))
    if len(set(header)) != len(header):
        raise InputError(path, header_line, f"duplicate column in header {','.join(header)}")
    missing = [n for n in expected if n not in header]
    if missing:
        raise InputError(path, header_line, f"wrong header: missing column(s) {','.join(missing)} "
                         f"(expected at least {','.join(expected)})")
    kinds = {}
    for name in header:
        c = schema.column(name)
        if c is None:
            allowed = [x.name for x in schema.required + schema.optional]
            extra = f" or names matching {schema.extra_pattern}" if schema.extra_pattern else ""
            raise InputError(path, header_line, f"wrong header: unknown column '{name}' "
                             f"(allowed: {','.join(allowed)}{extra}; see reports/FORMATS.md)")
        kinds[name] = c.kind
    table = Table(path=path, columns=header)
    for lineno, fields in records:
        if len(fields) != len(header):
            raise InputError(path, lineno, f"ragged row: {len(fields)} cells, header has {len(header)}")
        row: dict[str, object] = {}
        for name, text in zip(header, fields):
            if kinds[name] == "num":
                row[name] = parse_number(path, lineno, name, text, allow_empty_numbers)
            else:
                row[name] = text
        table.rows.append(row)
        table.lines.append(lineno)
    return table


def read_json(path: Path) -> dict:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as e:
        raise InputError(path, e.lineno, f"invalid JSON: {e.msg}") from None
    if not isinstance(data, dict):
        raise InputError(path, 1, "expected a JSON object")
    return data

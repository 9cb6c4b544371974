"""Loading and checking everything the report reads: reference rows, each
study's values.csv and meta.json, and the series files named in formats.py.
All parsing happens here, before any drawing, so a malformed file stops the
report at once (exit 2) instead of half-way through the PDF."""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from . import formats
from .csvio import InputError, Table, parse_number, read_json, read_table

TOLERANCE_KINDS = ("rel", "abs", "pct_points", "at_least", "at_most")
# What a row is evidence of (reference_data/README.md); only the first three are PASS/FAIL.
CLASSES = ("verification", "validation", "reproduction", "consistency")
UNCLASSIFIED = "unclassified"


@dataclass
class Reference:
    study: str
    id: str
    quantity: str
    unit: str
    value: float
    tolerance: float | None
    tolerance_kind: str
    gate: bool
    source: str
    provenance: str
    path: Path
    line: int
    row_class: str = UNCLASSIFIED
    u_ref: float | None = None  # standard uncertainty of the reference value (V&V 20's u_D)


@dataclass
class SeriesFile:
    name: str
    table: Table
    keys: dict[str, str]  # named groups parsed from the file name


@dataclass
class StudyResults:
    study: str
    folder: Path
    meta: dict | None = None
    values: dict[str, float] | None = None  # None: no values.csv
    series: dict[str, list[SeriesFile]] = field(default_factory=dict)  # pattern -> files
    unread: list[str] = field(default_factory=list)  # files the report does not know

    def files(self, pattern: str) -> list[SeriesFile]:
        return self.series.get(pattern, [])

    def one(self, pattern: str) -> SeriesFile | None:
        got = self.files(pattern)
        return got[0] if got else None


def _new_id(path: Path, line: int, row, seen, where: str = "") -> str:
    """The row's id; exit 2 naming file and line when it is empty or already in `seen`
    (`where` says where it was first)."""
    rid = str(row["id"])
    if not rid:
        raise InputError(path, line, "empty id")
    if rid in seen:
        raise InputError(path, line, f"duplicate id '{rid}'{where}")
    return rid


def load_references(ref_dir: Path) -> dict[str, list[Reference]]:
    refs: dict[str, list[Reference]] = {}
    seen: dict[str, str] = {}
    for path in sorted(ref_dir.glob("*.csv")):
        study = path.stem
        table = read_table(path, formats.REFERENCE)
        rows = []
        for r, line in zip(table.rows, table.lines):
            rid = _new_id(path, line, r, seen, f" (first at {seen.get(str(r['id']))})")
            seen[rid] = f"{path}:{line}"
            value = parse_number(path, line, "value", str(r["value"]), allow_empty=False)
            tol = parse_number(path, line, "tolerance", str(r["tolerance"]), allow_empty=True)
            kind = str(r["tolerance_kind"])
            if tol is not None:
                if kind not in TOLERANCE_KINDS:
                    raise InputError(path, line, f"tolerance_kind '{kind}' must be one of {', '.join(TOLERANCE_KINDS)}")
                if not tol >= 0 or math.isinf(tol):
                    raise InputError(path, line, f"tolerance {tol} must be a finite number >= 0")
            elif kind not in ("",) + TOLERANCE_KINDS:
                raise InputError(path, line, f"tolerance_kind '{kind}' must be empty or one of {', '.join(TOLERANCE_KINDS)}")
            gate = str(r["gate"])
            if gate not in ("yes", "no"):
                raise InputError(path, line, f"gate '{gate}' must be yes or no")
            row_class = str(r.get("class", "")) or UNCLASSIFIED
            if row_class not in CLASSES + (UNCLASSIFIED,):
                raise InputError(path, line, f"class '{row_class}' must be empty or one of {', '.join(CLASSES)}")
            u_ref = parse_number(path, line, "u_ref", str(r.get("u_ref", "")), allow_empty=True)
            if u_ref is not None and not (u_ref >= 0 and math.isfinite(u_ref)):
                raise InputError(path, line, f"u_ref {u_ref} must be a finite number >= 0")
            rows.append(Reference(study, rid, str(r["quantity"]), str(r["unit"]), float(value), tol, kind,
                                  gate == "yes", str(r["source"]), str(r["provenance"]), path, line, row_class, u_ref))
        refs[study] = rows
    return refs


def _load_values(path: Path) -> dict[str, float]:
    table = read_table(path, formats.VALUES)
    values: dict[str, float] = {}
    for r, line in zip(table.rows, table.lines):
        rid = _new_id(path, line, r, values)
        values[rid] = float(parse_number(path, line, "value", str(r["value"]), allow_empty=False))
    return values


def _check_meta(path: Path, study: str) -> dict:
    meta = read_json(path)
    kinds = {"study": str, "tier": str, "wall_time_s": (int, float), "passed": bool}
    for key, kind in kinds.items():
        if key not in meta:
            raise InputError(path, None, f"missing key '{key}' (expected {{\"study\",\"tier\",\"wall_time_s\",\"passed\"}})")
        if not isinstance(meta[key], kind) or (kind != bool and isinstance(meta[key], bool)):
            raise InputError(path, None, f"key '{key}' has the wrong type: {meta[key]!r}")
    if meta["study"] != study:
        raise InputError(path, None, f"study '{meta['study']}' does not match its folder '{study}'")
    return meta


def load_study(folder: Path, study: str, history: Path | None = None) -> StudyResults:
    res = StudyResults(study, folder)
    if (folder / "meta.json").is_file():
        res.meta = _check_meta(folder / "meta.json", study)
    if (folder / "values.csv").is_file():
        res.values = _load_values(folder / "values.csv")
    patterns = formats.PATTERNS.get(study, [])
    files = sorted(p for p in folder.iterdir() if p.is_file()) if folder.is_dir() else []
    if history is not None and study == "benchmarks":
        files = [p for p in files if p.name != "history.csv"] + [history]
    for path in files:
        if path.name in ("meta.json", "values.csv"):
            continue
        for pattern, schema, _template in patterns:
            m = re.fullmatch(pattern, path.name)
            if m:
                table = read_table(path, schema)
                res.series.setdefault(pattern, []).append(SeriesFile(path.name, table, m.groupdict()))
                break
        else:
            res.unread.append(path.name)
    return res


def load_results(results_dir: Path, history: Path | None = None) -> dict[str, StudyResults]:
    out: dict[str, StudyResults] = {}
    if results_dir.is_dir():
        for folder in sorted(p for p in results_dir.iterdir() if p.is_dir()):
            out[folder.name] = load_study(folder, folder.name, history)
    if history is not None and "benchmarks" not in out:
        out["benchmarks"] = load_study(results_dir / "benchmarks", "benchmarks", history)
    return out

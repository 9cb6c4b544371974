"""A study's own report code, in its folder: verification/<study>/report_figures.py
(the benchmarks': benchmarks/report_figures.py).

A new study needs no edit here or anywhere in reports/: it writes its results
through verification/support/study_io.hpp, adds reference_data/<study>.csv,
and (for plots) puts report_figures.py beside its check, defining any of

    TITLE = "Packed bed (Ergun pressure drop)"          # section title
    PATTERNS = [(regex, Schema, template), ...]         # its series files (formats.py types)
    def plots(results: StudyResults | None) -> list[Plot]   # its figures (figures.Plot)
    def check(results: StudyResults) -> None            # raise InputError before anything is drawn
    SECTIONS = {name: dict(title=..., patterns=..., plots=...)}  # further sections from the same folder

register() imports every such module once and adds it to the tables the
generator reads (formats.PATTERNS, formats.STUDIES, figures.PLOTTERS, CHECKS);
a module for a study the report already draws replaces that study's entry.
The report's order is formats.ORDER, then any other study alphabetically."""
from __future__ import annotations

import importlib.util
from pathlib import Path

from . import figures, formats
from .csvio import InputError

REGISTERED: dict[str, Path] = {}
CHECKS: dict = {}  # study -> check(results): the inputs a study checks before drawing


def _modules(source_dir: Path):
    """(study, path) of every study's report module in the tree."""
    for path in sorted(source_dir.glob("verification/*/report_figures.py")):
        yield path.parent.name, path
    bench = source_dir / "benchmarks" / "report_figures.py"
    if bench.is_file():
        yield "benchmarks", bench


def _add(study: str, title, patterns, plots) -> None:
    if patterns is not None:
        formats.PATTERNS[study] = list(patterns)
    if title is not None:
        formats.STUDIES[study] = str(title)
    if plots is not None:
        figures.PLOTTERS[study] = plots


def register(source_dir: Path) -> dict[str, Path]:
    for study, path in _modules(source_dir):
        if REGISTERED.get(study) == path:
            continue
        spec = importlib.util.spec_from_file_location(f"fdem_study_{study}_report", path)
        module = importlib.util.module_from_spec(spec)
        try:
            spec.loader.exec_module(module)
        except Exception as e:  # a broken study module stops the report, naming the file
            raise InputError(path, None, f"cannot import the study's report module: {e}") from None
        _add(study, getattr(module, "TITLE", None), getattr(module, "PATTERNS", None), getattr(module, "plots", None))
        if hasattr(module, "check"):
            CHECKS[study] = module.check
        for name, section in getattr(module, "SECTIONS", {}).items():
            _add(name, section.get("title"), section.get("patterns"), section.get("plots"))
            REGISTERED[name] = path
        REGISTERED[study] = path
    return REGISTERED

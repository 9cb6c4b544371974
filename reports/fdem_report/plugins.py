"""A study's own report code, in its folder: verification/<study>/report_figures.py.

A new study needs no edit here or anywhere in reports/: it writes its results
through verification/support/study_io.hpp, adds reference_data/<study>.csv,
and (for plots) puts report_figures.py beside its check, defining any of

    TITLE = "Packed bed (Ergun pressure drop)"          # section title
    PATTERNS = [(regex, Schema, template), ...]         # its series files (formats.py types)
    def plots(results: StudyResults | None) -> list[Plot]   # its figures (figures.Plot)

register() imports every such module once and adds it to the tables the
generator reads (formats.PATTERNS, formats.STUDIES, figures.PLOTTERS); a
module for a study the report already draws replaces that study's entry."""
from __future__ import annotations

import importlib.util
from pathlib import Path

from . import figures, formats
from .csvio import InputError

REGISTERED: dict[str, Path] = {}


def register(source_dir: Path) -> dict[str, Path]:
    for path in sorted(source_dir.glob("verification/*/report_figures.py")):
        study = path.parent.name
        if REGISTERED.get(study) == path:
            continue
        spec = importlib.util.spec_from_file_location(f"fdem_study_{study}_report", path)
        module = importlib.util.module_from_spec(spec)
        try:
            spec.loader.exec_module(module)
        except Exception as e:  # a broken study module stops the report, naming the file
            raise InputError(path, None, f"cannot import the study's report module: {e}") from None
        if hasattr(module, "PATTERNS"):
            formats.PATTERNS[study] = list(module.PATTERNS)
        if hasattr(module, "TITLE"):
            formats.STUDIES[study] = str(module.TITLE)
        if hasattr(module, "plots"):
            figures.PLOTTERS[study] = module.plots
        REGISTERED[study] = path
    return REGISTERED

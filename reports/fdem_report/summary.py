"""The summary table: each reference row beside our value, the deviation and
the verdict. A study that did not run, or did not measure a row, is NOT RUN,
never PASS; a row without a tolerance is INFO (tabulated, not judged)."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .inputs import Reference, StudyResults

PASS, FAIL, NOT_RUN, INFO = "PASS", "FAIL", "NOT RUN", "INFO"
STATUSES = (FAIL, NOT_RUN, PASS, INFO)


@dataclass
class Row:
    ref: Reference
    ours: float | None
    status: str
    note: str = ""

    @property
    def dev_abs(self) -> float | None:
        if self.ours is None:
            return None
        return self.ours - self.ref.value

    @property
    def dev_pct(self) -> float | None:
        if self.ours is None or self.ref.value == 0:
            return None
        return 100.0 * (self.ours - self.ref.value) / abs(self.ref.value)

    @property
    def allowed_abs(self) -> float | None:
        """The tolerance as an absolute deviation in the row's unit."""
        return allowed_deviation(self.ref)


def allowed_deviation(ref: Reference) -> float | None:
    if ref.tolerance is None:
        return None
    if ref.tolerance_kind == "rel":
        return ref.tolerance * abs(ref.value)
    return ref.tolerance  # abs, and pct_points for values in percent


def tolerance_text(ref: Reference) -> str:
    if ref.tolerance is None:
        return ""
    if ref.tolerance_kind == "rel":
        return f"±{100 * ref.tolerance:.3g} %"
    if ref.tolerance_kind == "pct_points":
        return f"±{ref.tolerance:.3g} pp"
    unit = "" if ref.unit in ("-", "") else " " + ref.unit
    return f"±{ref.tolerance:.3g}{unit}"


def judge(ref: Reference, study: StudyResults | None) -> Row:
    if study is None or study.values is None:
        why = "study not run" if study is None or study.meta is None else "study wrote no values.csv"
        return Row(ref, None, NOT_RUN, why)
    if ref.id not in study.values:
        tier = study.meta.get("tier") if study.meta else None
        return Row(ref, None, NOT_RUN, f"not measured{f' in tier {tier}' if tier else ''}")
    ours = study.values[ref.id]
    allowed = allowed_deviation(ref)
    if allowed is None:
        return Row(ref, ours, INFO, "no tolerance: tabulated, not judged")
    if not math.isfinite(ours):
        return Row(ref, ours, FAIL, "our value is not finite")
    # Round-off slack: a deviation equal to the tolerance up to the last few
    # bits of the numbers passes (values are written with ~15 digits).
    slack = 1e-12 * max(abs(ours), abs(ref.value))
    ok = abs(ours - ref.value) <= allowed + slack
    return Row(ref, ours, PASS if ok else FAIL)


def build_rows(refs: dict[str, list[Reference]], results: dict[str, StudyResults]) -> list[Row]:
    rows = []
    for study in refs:
        for ref in refs[study]:
            rows.append(judge(ref, results.get(study)))
    return rows


def counts(rows: list[Row]) -> dict[str, int]:
    c = {s: 0 for s in STATUSES}
    for r in rows:
        c[r.status] += 1
    return c


def fmt(x: float | None, digits: int = 4) -> str:
    if x is None:
        return ""
    if math.isnan(x):
        return "nan"
    return f"{x:.{digits}g}"

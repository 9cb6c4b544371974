"""The summary table: each reference row beside our value, the deviation and
the verdict. A study that did not run, or did not measure a row, is NOT RUN,
never PASS; a row without a tolerance is INFO (tabulated, not judged); a row
of class consistency (input echo, closed-form arithmetic: no solver ran) is
CONSISTENT or MISMATCH, never PASS/FAIL; a row whose study ran on another
commit, or on a scene that has changed since, is STALE (its value shown, not
judged)."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .inputs import Reference, StudyResults

PASS, FAIL, NOT_RUN, INFO = "PASS", "FAIL", "NOT RUN", "INFO"
CONSISTENT, MISMATCH, STALE = "CONSISTENT", "MISMATCH", "STALE"
STATUSES = (FAIL, MISMATCH, STALE, NOT_RUN, PASS, CONSISTENT, INFO)
JUDGED = (PASS, FAIL)  # the only verdicts that count as evidence for or against the solver


@dataclass
class Row:
    ref: Reference
    ours: float | None
    status: str
    note: str = ""
    tier: str = ""       # the tier (meta.json) that produced our value
    when: str = ""       # when that run finished (UTC)
    u_num: float | None = None    # numerical uncertainty of ours (refinement), same unit
    u_input: float | None = None  # input-parameter uncertainty of ours, same unit

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

    @property
    def u_val(self) -> float | None:
        """ASME V&V 20 validation uncertainty sqrt(u_num^2 + u_input^2 + u_D^2)
        over the components that are known (None when none is)."""
        parts = [u for u in (self.u_num, self.u_input, self.ref.u_ref) if u is not None and math.isfinite(u)]
        return math.sqrt(sum(u * u for u in parts)) if parts else None


def allowed_deviation(ref: Reference) -> float | None:
    if ref.tolerance is None:
        return None
    if ref.tolerance_kind == "rel":
        return ref.tolerance * abs(ref.value)
    return ref.tolerance  # abs, pct_points (values in percent), and the one-sided kinds


def tolerance_text(ref: Reference) -> str:
    if ref.tolerance is None:
        return ""
    unit = "" if ref.unit in ("-", "") else " " + ref.unit
    if ref.tolerance_kind == "rel":
        return f"±{100 * ref.tolerance:.3g} %"
    if ref.tolerance_kind == "pct_points":
        return f"±{ref.tolerance:.3g} pp"
    if ref.tolerance_kind == "at_least":
        return f"≥ {ref.value - ref.tolerance:.4g}{unit}"
    if ref.tolerance_kind == "at_most":
        return f"≤ {ref.value + ref.tolerance:.4g}{unit}"
    return f"±{ref.tolerance:.3g}{unit}"


def within(ref: Reference, ours: float) -> bool:
    allowed = allowed_deviation(ref)
    # Round-off slack: a deviation equal to the tolerance up to the last few
    # bits of the numbers passes (values are written with ~15 digits).
    slack = 1e-12 * max(abs(ours), abs(ref.value))
    if ref.tolerance_kind == "at_least":
        return ours >= ref.value - allowed - slack
    if ref.tolerance_kind == "at_most":
        return ours <= ref.value + allowed + slack
    return abs(ours - ref.value) <= allowed + slack


def _optional_value(values: dict, key: str) -> float | None:
    v = values.get(key)
    return v if v is not None and math.isfinite(v) else None


def judge(ref: Reference, study: StudyResults | None, stale: str = "") -> Row:
    """`stale`: why the study's results are not this commit's (empty: they are)."""
    if study is None or study.values is None:
        why = "study not run" if study is None or study.meta is None else "study wrote no values.csv"
        return Row(ref, None, NOT_RUN, why)
    meta = study.meta or {}
    tier, when = str(meta.get("tier", "")), str(meta.get("finished_utc", ""))
    if ref.id not in study.values:
        return Row(ref, None, NOT_RUN, f"not measured{f' in tier {tier}' if tier else ''}", tier, when)
    ours = study.values[ref.id]
    row = Row(ref, ours, INFO, "", tier, when, _optional_value(study.values, ref.id + ".u_num"),
              _optional_value(study.values, ref.id + ".u_input"))
    if stale:
        row.status, row.note = STALE, stale
        return row
    consistency = ref.row_class == "consistency"
    if allowed_deviation(ref) is None:
        row.note = "no tolerance: tabulated, not judged"
        return row
    if not math.isfinite(ours):
        row.status, row.note = (MISMATCH if consistency else FAIL), "our value is not finite"
        return row
    ok = within(ref, ours)
    if consistency:
        row.status = CONSISTENT if ok else MISMATCH
        row.note = "consistency check (no solver run): never counted as a pass"
    else:
        row.status = PASS if ok else FAIL
        if ref.row_class not in ("verification", "validation", "reproduction"):
            row.note = "unclassified row (no class in reference_data)"
    return row


def build_rows(refs: dict[str, list[Reference]], results: dict[str, StudyResults],
               stale: dict[str, str] | None = None) -> list[Row]:
    rows = []
    stale = stale or {}
    for study in refs:
        for ref in refs[study]:
            rows.append(judge(ref, results.get(study), stale.get(study, "")))
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

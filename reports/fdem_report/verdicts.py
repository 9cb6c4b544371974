"""Page 1 in sentences: per study, what was verified, validated against
experiment and reproduced from the paper, what disagrees (with the reason its
reference row gives), what was not run; and the ASME V&V 20 comparison
(E = S - D beside u_num, u_input, u_D) for every validation and reproduction
row. Built from the rows alone, so a new study appears without code here."""
from __future__ import annotations

import math

from .summary import CONSISTENT, FAIL, INFO, MISMATCH, NOT_RUN, PASS, STALE, Row, fmt, tolerance_text

CLASS_WORDS = {
    "verification": "Solver verification",
    "validation": "Validation against experiment",
    "reproduction": "Reproduction of the paper",
    "unclassified": "Unclassified rows",
}


def _value_text(r: Row) -> str:
    dev = f", {r.dev_pct:+.3g} %" if r.dev_pct is not None else f", deviation {fmt(r.dev_abs, 3)}"
    return f"{r.ref.id} (ours {fmt(r.ours)} vs {fmt(r.ref.value)} {r.ref.unit}{dev}"


def study_verdict(study) -> list[str]:
    """Sentences for one study (a StudySection of generate.py)."""
    rows: list[Row] = study.rows
    out: list[str] = []
    meta = study.results.meta if study.results else None
    if not rows and not meta:
        if study.results and study.results.series:
            return ["Figures only: this folder has no reference rows and no meta.json (see its plots)."]
        return ["Not run: no results and no reference rows."]
    if meta:
        out.append(f"Ran in tier {meta.get('tier', '?')}"
                   + (f", finished {meta['finished_utc']}" if meta.get("finished_utc") else "")
                   + f"; the study's own gates {'passed' if meta.get('passed') else 'FAILED'}.")
    else:
        out.append("Not run: every row below is NOT RUN.")
    stale = [r for r in rows if r.status == STALE]
    if stale:
        out.append(f"{len(stale)} row(s) are STALE and not judged: {stale[0].note}.")
    for cls, words in CLASS_WORDS.items():
        mine = [r for r in rows if r.ref.row_class == cls]
        if not mine:
            continue
        judged = [r for r in mine if r.status in (PASS, FAIL)]
        fails = [r for r in mine if r.status == FAIL]
        notrun = [r for r in mine if r.status == NOT_RUN]
        info = [r for r in mine if r.status == INFO and r.ours is not None]
        text = f"{words}: "
        if judged:
            text += f"{len(judged) - len(fails)} of {len(judged)} judged rows PASS"
        else:
            text += "no judged row"
        if fails:
            text += "; FAIL: " + "; ".join(f"{_value_text(r)}, tolerance {tolerance_text(r.ref)})" for r in fails)
        if info and cls in ("validation", "reproduction"):
            worst = max(info, key=lambda r: abs(r.dev_pct) if r.dev_pct is not None else 0.0)
            text += (f"; {len(info)} row(s) tabulated beside the reference without a tolerance, the largest "
                     f"difference {_value_text(worst)})")
        if notrun:
            text += f"; {len(notrun)} NOT RUN ({notrun[0].note})"
        out.append(text + ".")
        # Why it disagrees, in the words of the reference rows (each reason once).
        # A short provenance ("as r3") points at a sibling row: give the first full one of the class.
        explained = [r for r in mine if len(r.ref.provenance) > 40]
        seen = set()
        for r in fails + ([max(info, key=lambda r: abs(r.dev_pct or 0.0))] if info and cls != "verification" else []):
            why = r if len(r.ref.provenance) > 40 or not explained else explained[0]
            if why.ref.provenance and why.ref.provenance not in seen:
                seen.add(why.ref.provenance)
                out.append(f"Why ({why.ref.id}): {why.ref.provenance}")
    cons = [r for r in rows if r.ref.row_class == "consistency"]
    if cons:
        ok = sum(r.status == CONSISTENT for r in cons)
        bad = [r for r in cons if r.status == MISMATCH]
        out.append(f"Consistency checks (input echo, closed-form arithmetic; no solver ran, not counted as "
                   f"passes): {ok} consistent" + (f", {len(bad)} MISMATCH: " + "; ".join(_value_text(r) + ")"
                                                                                   for r in bad) if bad else "") + ".")
    return out


def vv20_rows(rows: list[Row]) -> list[dict]:
    """One comparison per validation or reproduction row that has our value."""
    out = []
    for r in rows:
        if r.ref.row_class not in ("validation", "reproduction") or r.ours is None or not math.isfinite(r.ours):
            continue
        if r.ref.tolerance_kind in ("at_least", "at_most"):
            continue  # a threshold, not a measured reference value: no comparison error
        e = r.ours - r.ref.value
        u_val = r.u_val
        if u_val is None or u_val == 0.0:
            reading = "no uncertainty estimated: E cannot be weighed"
        elif abs(e) > 2.0 * u_val:
            reading = f"|E| = {abs(e) / u_val:.3g} u_val: a model (or reference) difference beyond the uncertainties"
        else:
            reading = f"|E| = {abs(e) / u_val:.2g} u_val: no difference detectable beyond the uncertainties"
        missing = [name for name, u in (("u_num", r.u_num), ("u_input", r.u_input), ("u_D", r.ref.u_ref))
                   if u is None]
        out.append({
            "id": r.ref.id, "class": r.ref.row_class, "unit": r.ref.unit, "S": r.ours, "D": r.ref.value, "E": e,
            "E_pct": r.dev_pct, "u_num": r.u_num, "u_input": r.u_input, "u_D": r.ref.u_ref, "u_val": u_val,
            "reading": reading + (f" (not estimated: {', '.join(missing)})" if missing else ""),
            "status": r.status,
        })
    return out

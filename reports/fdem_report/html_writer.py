"""index.html: one self-contained file (figures embedded as base64 PNG, CSS
inline, no scripts, no external resources)."""
from __future__ import annotations

import base64
import html
import io

from .summary import FAIL, MISMATCH, STATUSES, Row, fmt, tolerance_text

CSS = """
body{font-family:DejaVu Sans,Helvetica,Arial,sans-serif;margin:1.5em auto;max-width:1250px;color:#222;font-size:14px}
h1{margin-bottom:0.2em} h2{border-bottom:2px solid #888;margin-top:2em} h3{margin-bottom:0.3em}
table{border-collapse:collapse;margin:0.5em 0;font-size:12px}
th,td{border:1px solid #bbb;padding:2px 6px;vertical-align:top}
th{background:#eee;text-align:left} td.num{text-align:right;font-variant-numeric:tabular-nums;white-space:nowrap}
tr.FAIL td{background:#f8d0d0} tr.FAIL td.status{background:#c62828;color:#fff;font-weight:bold}
tr.PASS td.status{background:#2e7d32;color:#fff} tr.NOTRUN td{color:#666;background:#f3f3f3}
tr.NOTRUN td.status{background:#9e9e9e;color:#fff} tr.INFO td.status{background:#1565c0;color:#fff}
tr.study td{background:#dde4ee;font-weight:bold}
tr.MISMATCH td.status{background:#c62828;color:#fff} tr.CONSISTENT td.status{background:#6a8f6b;color:#fff}
tr.STALE td{color:#666;background:#fbeee0} tr.STALE td.status{background:#e65100;color:#fff}
td{overflow-wrap:anywhere} td.num{overflow-wrap:normal} code{overflow-wrap:anywhere}
.verdict p{margin:0.2em 0 0.2em 1em} .verdict h3{margin:0.8em 0 0.1em 0}
.banner{display:flex;gap:1em;margin:1em 0} .badge{padding:0.5em 1em;border-radius:4px;font-size:18px;color:#fff}
.b-FAIL{background:#c62828} .b-PASS{background:#2e7d32} .b-NOTRUN{background:#9e9e9e} .b-INFO{background:#1565c0}
.b-MISMATCH{background:#c62828} .b-CONSISTENT{background:#6a8f6b} .b-STALE{background:#e65100}
.notrun{background:#fff3cd;border:1px solid #e0c060;padding:0.4em 0.8em;margin:0.5em 0}
.small{font-size:11px;color:#555} img{max-width:100%;border:1px solid #ddd;margin:0.5em 0}
"""


def _e(x) -> str:
    return html.escape(str(x), quote=True)


def _cls(status: str) -> str:
    return status.replace(" ", "")


def png_base64(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _row_cells(r: Row, with_provenance: bool) -> str:
    ref = r.ref
    cells = [
        f'<td class="status">{_e(r.status)}</td>',
        f"<td>{_e(ref.row_class)}</td>",
        f"<td><code>{_e(ref.id)}</code></td>",
        f"<td>{_e(ref.quantity)}</td>",
        f'<td class="num">{_e(fmt(r.ours))}</td>',
        f'<td class="num">{_e(fmt(ref.value))}</td>',
        f"<td>{_e(ref.unit)}</td>",
        f'<td class="num">{_e(fmt(r.dev_abs, 3))}</td>',
        f'<td class="num">{_e(fmt(r.dev_pct, 3))}</td>',
        f'<td class="num">{_e(tolerance_text(ref))}</td>',
        f"<td>{'yes' if ref.gate else 'no'}</td>",
        f'<td class="small">{_e(r.tier)}<br>{_e(r.when)}</td>',
        f"<td>{_e(ref.source)}</td>",
    ]
    if with_provenance:
        cells.append(f'<td class="small">{_e(ref.provenance)}'
                     + (f"<br><b>{_e(r.note)}</b>" if r.note else "") + "</td>")
    else:
        cells.append(f'<td class="small">{_e(r.note)}</td>')
    return f'<tr class="{_cls(r.status)}">' + "".join(cells) + "</tr>"


def _rows_table(rows: list[Row], with_provenance: bool, group: bool) -> str:
    head = ["status", "class", "id", "quantity", "ours", "reference", "unit", "deviation", "dev. %", "tolerance",
            "ctest gate", "run", "source", "provenance / note" if with_provenance else "note"]
    out = ["<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>"]
    study = None
    for r in rows:
        if group and r.ref.study != study:
            study = r.ref.study
            out.append(f'<tr class="study"><td colspan="{len(head)}"><a href="#study-{_e(study)}">{_e(study)}</a>'
                       f' <span class="small">({_e(r.ref.path.name)})</span></td></tr>')
        out.append(_row_cells(r, with_provenance))
    out.append("</table>")
    return "\n".join(out)


def _vv20_table(rows: list[dict]) -> str:
    out = ['<h2 id="vv20">Validation and reproduction: comparison error and uncertainties (ASME V&amp;V 20)</h2>',
           '<p class="small">E = S - D (simulation minus reference). u_num: numerical uncertainty of S from '
           "systematic refinement (verification/support/grid_convergence.hpp: GCI over three fluid steps or meshes, "
           "divided by 1.15); u_input: from the uncertainty of the inputs; u_D: of the reference value as its "
           "source gives it (reference_data u_ref). u_val = sqrt(u_num^2 + u_input^2 + u_D^2) over the known "
           "parts. |E| well above u_val means a difference of model (or of the reference) that the uncertainties "
           "cannot explain. An empty cell is not estimated; the reading says which.</p>"]
    if not rows:
        return "\n".join(out + ['<p class="notrun">No validation or reproduction row has a value yet.</p>'])
    head = ["id", "class", "S (ours)", "D (reference)", "E", "E %", "u_num", "u_input", "u_D", "u_val", "reading"]
    out.append("<table><tr>" + "".join(f"<th>{h}</th>" for h in head) + "</tr>")
    for v in rows:
        out.append(f'<tr class="{_cls(v["status"])}"><td><code>{_e(v["id"])}</code></td><td>{_e(v["class"])}</td>'
                   + "".join(f'<td class="num">{_e(fmt(v[k], 4))}</td>'
                             for k in ("S", "D", "E", "E_pct", "u_num", "u_input", "u_D", "u_val"))
                   + f'<td class="small">{_e(v["reading"])}</td></tr>')
    out.append("</table>")
    return "\n".join(out)


def write(path, report) -> None:
    c = report.counts
    parts = [f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
             f"<title>fdem validation report</title><style>{CSS}</style></head><body>",
             "<h1>fdem validation report</h1>",
             f'<p class="small">{_e(report.headline)}</p>',
             '<div class="banner">' + "".join(
                 f'<span class="badge b-{_cls(s)}">{c[s]} {s}</span>' for s in STATUSES) + "</div>"]
    if c[FAIL] or c[MISMATCH]:
        parts.append(f'<p><b style="color:#c62828">{c[FAIL] + c[MISMATCH]} reference value(s) outside tolerance:</b> '
                     + ", ".join(f'<code>{_e(r.ref.id)}</code>' for r in report.rows if r.status in (FAIL, MISMATCH))
                     + "</p>")
    parts.append('<div class="verdict"><h2 id="verdict">Verdict, study by study</h2>')
    for s in report.studies:
        parts.append(f'<h3><a href="#study-{_e(s.name)}">{_e(s.title)}</a></h3>')
        parts.extend(f"<p>{_e(t)}</p>" for t in s.sentences)
    parts.append("</div>")
    parts.append(_vv20_table(report.vv20))
    parts.append("<p>Contents: <a href=\"#verdict\">verdict</a> · <a href=\"#vv20\">V&amp;V 20</a> · "
                 "<a href=\"#summary\">summary</a> · <a href=\"#studies\">studies</a> · "
                 + " · ".join(f'<a href="#study-{_e(s.name)}">{_e(s.name)}</a>' for s in report.studies)
                 + ' · <a href="#provenance">provenance</a></p>')
    parts.append('<h2 id="summary">Summary: every reference value beside ours</h2>')
    parts.append(f"<p class=\"small\">{_e(report.legend)}</p>")
    parts.append(_rows_table(report.rows, with_provenance=False, group=True) if report.rows
                 else '<p class="notrun">No reference rows found in reference_data/.</p>')
    parts.append('<h2 id="studies">Studies</h2><table><tr><th>study</th><th>tier</th><th>wall time [s]</th>'
                 "<th>study's own verdict</th>" + "".join(f"<th>{s}</th>" for s in STATUSES)
                 + "<th>run provenance</th></tr>")
    for s in report.studies:
        verdict = s.verdict
        cls = {"failed": "FAIL", "not run": "NOTRUN", "stale": "STALE"}.get(verdict, "")
        parts.append(f'<tr class="{cls}"><td><a href="#study-{_e(s.name)}">{_e(s.name)}</a></td>'
                     f"<td>{_e(s.tier)}</td><td class=\"num\">{_e(s.wall_time)}</td><td>{_e(verdict)}</td>"
                     + "".join(f'<td class="num">{s.counts[k]}</td>' for k in STATUSES)
                     + f'<td class="small">{_e(s.stale or s.run_provenance)}</td></tr>')
    parts.append("</table>")
    for s in report.studies:
        parts.append(f'<h2 id="study-{_e(s.name)}">{_e(s.title)}</h2>')
        parts.append(f'<p class="small">study <code>{_e(s.name)}</code>; tier {_e(s.tier)}; wall time '
                     f"{_e(s.wall_time)} s; its own verdict: {_e(s.verdict)}; {_e(s.run_provenance)}</p>")
        if s.stale:
            parts.append(f'<p class="notrun">{_e(s.stale)}</p>')
        if s.verdict == "not run":
            parts.append(f'<p class="notrun">NOT RUN: no results in {_e(s.folder)}</p>')
        if s.rows:
            parts.append(_rows_table(s.rows, with_provenance=True, group=False))
        if s.unreferenced:
            parts.append("<h3>Measured, no reference row</h3><table><tr><th>id</th><th>value</th></tr>"
                         + "".join(f'<tr><td><code>{_e(k)}</code></td><td class="num">{_e(fmt(v))}</td></tr>'
                                   for k, v in s.unreferenced) + "</table>")
        for p in s.plots:
            parts.append(f"<h3>{_e(p.title)}</h3>")
            if p.fig is not None:
                parts.append(f'<img alt="{_e(p.title)}" src="data:image/png;base64,{p.png}">')
            if p.note:
                parts.append(f'<p class="{"notrun" if p.fig is None else "small"}">{_e(p.note)}</p>')
        if s.unread:
            parts.append('<p class="small">Files in the results folder this report does not read: '
                         + ", ".join(f"<code>{_e(n)}</code>" for n in s.unread) + "</p>")
    parts.append('<h2 id="provenance">Provenance</h2><table>'
                 + "".join(f"<tr><th>{_e(k)}</th><td>{_e(v)}</td></tr>" for k, v in report.provenance)
                 + "</table><table><tr><th>study</th><th>tier</th><th>wall time [s]</th></tr>"
                 + "".join(f"<tr><td>{_e(s.name)}</td><td>{_e(s.tier)}</td><td class=\"num\">{_e(s.wall_time)}</td></tr>"
                           for s in report.studies)
                 + "</table>")
    parts.append("</body></html>\n")
    path.write_text("\n".join(parts), encoding="utf-8")

"""report.pdf via matplotlib's PdfPages: a cover page with the counts and
provenance, the summary table drawn as figure pages, then per study a text page
(its rows with provenance, notes of what did not run) and its plots."""
from __future__ import annotations

import textwrap

from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from .figures import A4_LANDSCAPE
from .summary import FAIL, INFO, NOT_RUN, PASS, STATUSES, fmt, tolerance_text

COLOURS = {FAIL: "#f4b4b4", PASS: "#c8e6c9", NOT_RUN: "#e0e0e0", INFO: "#cfe0f5"}
STRONG = {FAIL: "#c62828", PASS: "#2e7d32", NOT_RUN: "#757575", INFO: "#1565c0"}
ROWS_PER_PAGE = 32
LINES_PER_PAGE = 62


def _cut(s: str, n: int) -> str:
    s = str(s)
    return s if len(s) <= n else s[: n - 1] + "…"


def _page(title: str) -> Figure:
    fig = Figure(figsize=A4_LANDSCAPE)
    fig.text(0.04, 0.955, title, fontsize=14, weight="bold", va="top")
    return fig


def _cover(report) -> Figure:
    fig = _page("fdem validation report")
    fig.text(0.04, 0.91, report.headline, fontsize=8, va="top", color="#444")
    x = 0.04
    for s in STATUSES:
        fig.text(x, 0.85, f" {report.counts[s]} {s} ", fontsize=16, color="white", va="top",
                 bbox=dict(facecolor=STRONG[s], edgecolor="none", boxstyle="round,pad=0.3"))
        x += 0.17
    y = 0.76
    fails = [r.ref.id for r in report.rows if r.status == FAIL]
    if fails:
        text = "Outside tolerance: " + ", ".join(fails)
        for line in textwrap.wrap(text, 150)[:5]:
            fig.text(0.04, y, line, fontsize=8, color=STRONG[FAIL], va="top", weight="bold")
            y -= 0.025
    fig.text(0.04, y - 0.01, report.legend, fontsize=7, color="#444", va="top", wrap=True)
    ax = fig.add_axes((0.04, 0.08, 0.52, y - 0.12))
    ax.axis("off")
    cells = [[s.name, s.tier, s.wall_time, s.verdict] + [str(s.counts[k]) for k in STATUSES] for s in report.studies]
    if cells:
        tab = ax.table(cellText=cells, colLabels=["study", "tier", "wall [s]", "verdict"] + list(STATUSES),
                       loc="upper left", cellLoc="left",
                       colWidths=[0.22, 0.08, 0.1, 0.12, 0.12, 0.12, 0.12, 0.12])
        tab.auto_set_font_size(False)
        tab.set_fontsize(7)
        for i, s in enumerate(report.studies, start=1):
            if s.verdict in ("failed", "not run"):
                for j in range(4):
                    tab[i, j].set_facecolor(COLOURS[FAIL] if s.verdict == "failed" else COLOURS[NOT_RUN])
    ax2 = fig.add_axes((0.60, 0.08, 0.37, y - 0.12))
    ax2.axis("off")
    tab = ax2.table(cellText=[[k, _cut(v, 60)] for k, v in report.provenance], loc="upper left",
                    cellLoc="left", colWidths=[0.3, 0.7])
    tab.auto_set_font_size(False)
    tab.set_fontsize(7)
    return fig


def _summary_pages(rows, title):
    cols = ["status", "id", "quantity", "ours", "reference", "unit", "dev.", "dev. %", "tolerance", "gate", "source"]
    widths = [0.055, 0.22, 0.14, 0.06, 0.06, 0.045, 0.06, 0.05, 0.06, 0.035, 0.205]
    pages = []
    for start in range(0, max(len(rows), 1), ROWS_PER_PAGE):
        chunk = rows[start:start + ROWS_PER_PAGE]
        n_pages = max(1, -(-len(rows) // ROWS_PER_PAGE))
        fig = _page(f"{title} ({start // ROWS_PER_PAGE + 1}/{n_pages})")
        ax = fig.add_axes((0.02, 0.03, 0.96, 0.88))
        ax.axis("off")
        if not chunk:
            ax.text(0, 1, "No reference rows.", va="top")
            pages.append(fig)
            continue
        cells = [[r.status, _cut(r.ref.id, 48), _cut(r.ref.quantity, 32), fmt(r.ours), fmt(r.ref.value),
                  _cut(r.ref.unit, 8), fmt(r.dev_abs, 3), fmt(r.dev_pct, 3), tolerance_text(r.ref),
                  "yes" if r.ref.gate else "no", _cut(r.ref.source, 52)] for r in chunk]
        tab = ax.table(cellText=cells, colLabels=cols, colWidths=widths, loc="upper center", cellLoc="left")
        tab.auto_set_font_size(False)
        tab.set_fontsize(6.5)
        tab.scale(1, 1.05)
        for i, r in enumerate(chunk, start=1):
            tab[i, 0].set_facecolor(STRONG[r.status])
            tab[i, 0].get_text().set_color("white")
            tab[i, 0].get_text().set_weight("bold")
            if r.status in (FAIL, NOT_RUN):
                for j in range(1, len(cols)):
                    tab[i, j].set_facecolor(COLOURS[r.status])
        pages.append(fig)
    return pages


def _text_pages(title: str, lines: list[tuple[str, str]]):
    """lines: (text, colour); wrapped and paginated."""
    wrapped = []
    for text, colour in lines:
        for w in textwrap.wrap(text, 175, subsequent_indent="      ") or [""]:
            wrapped.append((w, colour))
    pages = []
    for start in range(0, max(len(wrapped), 1), LINES_PER_PAGE):
        fig = _page(title if start == 0 else title + " (cont.)")
        y = 0.91
        for text, colour in wrapped[start:start + LINES_PER_PAGE]:
            fig.text(0.04, y, text, fontsize=7, family="monospace", color=colour, va="top")
            y -= 0.0138
        pages.append(fig)
    return pages


def _study_lines(s):
    lines = [(f"study '{s.name}': tier {s.tier}, wall time {s.wall_time} s, its own verdict: {s.verdict}",
              STRONG[FAIL] if s.verdict == "failed" else "black")]
    if s.verdict == "not run":
        lines.append((f"NOT RUN: no results in {s.folder}", STRONG[NOT_RUN]))
    if s.rows:
        lines.append(("", "black"))
        lines.append(("Reference rows (status, id: ours vs reference; source; provenance):", "black"))
    for r in s.rows:
        colour = STRONG[r.status] if r.status in (FAIL, NOT_RUN) else "black"
        lines.append((f"{r.status:7s} {r.ref.id}: ours {fmt(r.ours) or '-'} vs {fmt(r.ref.value)} {r.ref.unit}"
                      f" (dev {fmt(r.dev_pct, 3) or '-'} %, tol {tolerance_text(r.ref) or 'none'})"
                      f"{'; ' + r.note if r.note else ''}", colour))
        lines.append((f"      source: {r.ref.source}; provenance: {r.ref.provenance}", "#555555"))
    if s.unreferenced:
        lines.append(("", "black"))
        lines.append(("Measured, no reference row: " + ", ".join(f"{k} = {fmt(v)}" for k, v in s.unreferenced),
                      "black"))
    missing = [p for p in s.plots if p.fig is None]
    if missing:
        lines.append(("", "black"))
    for p in missing:
        lines.append((f"Plot '{p.title}': {p.note}", STRONG[NOT_RUN]))
    for p in s.plots:
        if p.fig is not None and p.note:
            lines.append((f"Plot '{p.title}': {p.note}", "black"))
    if s.unread:
        lines.append(("Files this report does not read: " + ", ".join(s.unread), "#555555"))
    return lines


def write(path, report) -> None:
    with PdfPages(path) as pdf:
        pdf.savefig(_cover(report))
        for fig in _summary_pages(report.rows, "Summary: every reference value beside ours"):
            pdf.savefig(fig)
        for s in report.studies:
            for fig in _text_pages(s.title, _study_lines(s)):
                pdf.savefig(fig)
            for p in s.plots:
                if p.fig is not None:
                    pdf.savefig(p.fig)
        for fig in _text_pages("Provenance", [(f"{k:20s} {v}", "black") for k, v in report.provenance]
                               + [("", "black")]
                               + [(f"{s.name:20s} tier {s.tier:6s} wall time {s.wall_time} s", "black")
                                  for s in report.studies]):
            pdf.savefig(fig)
        info = pdf.infodict()
        info["Title"] = "fdem validation report"
        info["Subject"] = report.headline

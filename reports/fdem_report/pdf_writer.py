"""report.pdf via matplotlib's PdfPages: a cover page with the counts, the
verdict per study in sentences and the provenance, the V&V 20 comparison and
the summary table drawn as figure pages (cells wrap, never cut), then per
study a text page (its rows with provenance, notes of what did not run) and
its plots."""
from __future__ import annotations

import textwrap

from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

from .figures import A4_LANDSCAPE
from matplotlib.patches import Rectangle

from .summary import CONSISTENT, FAIL, INFO, MISMATCH, NOT_RUN, PASS, STALE, STATUSES, fmt, tolerance_text

COLOURS = {FAIL: "#f4b4b4", PASS: "#c8e6c9", NOT_RUN: "#e0e0e0", INFO: "#cfe0f5", MISMATCH: "#f4b4b4",
           CONSISTENT: "#dfeadf", STALE: "#fbe3cc"}
STRONG = {FAIL: "#c62828", PASS: "#2e7d32", NOT_RUN: "#757575", INFO: "#1565c0", MISMATCH: "#c62828",
          CONSISTENT: "#6a8f6b", STALE: "#e65100"}
ROWS_PER_PAGE = 32
LINES_PER_PAGE = 62


def _page(title: str) -> Figure:
    fig = Figure(figsize=A4_LANDSCAPE)
    fig.text(0.04, 0.955, title, fontsize=14, weight="bold", va="top")
    return fig


def _cover(report) -> Figure:
    fig = _page("fdem validation report")
    fig.text(0.04, 0.91, report.headline, fontsize=8, va="top", color="#444")
    x = 0.04
    for s in STATUSES:
        fig.text(x, 0.85, f" {report.counts[s]} {s} ", fontsize=12, color="white", va="top",
                 bbox=dict(facecolor=STRONG[s], edgecolor="none", boxstyle="round,pad=0.3"))
        x += 0.135
    y = 0.76
    fails = [r.ref.id for r in report.rows if r.status in (FAIL, MISMATCH)]
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
                       colWidths=[0.2, 0.07, 0.08, 0.08] + [0.08] * len(STATUSES))
        tab.auto_set_font_size(False)
        tab.set_fontsize(7)
        for i, s in enumerate(report.studies, start=1):
            if s.verdict in ("failed", "not run", "stale"):
                for j in range(4):
                    tab[i, j].set_facecolor(COLOURS[{"failed": FAIL, "stale": STALE}.get(s.verdict, NOT_RUN)])
    yy = y - 0.02
    for k, v in report.provenance:
        for i, line in enumerate(textwrap.wrap(f"{k}: {v}", 75) or [""]):
            fig.text(0.60, yy, ("" if i == 0 else "    ") + line, fontsize=6.5, va="top", color="#333333")
            yy -= 0.018
    return fig


def _wrapped_table_pages(title: str, head: list[str], widths: list[float], rows: list[list[str]],
                         colours: list[str | None], fontsize: float = 6.0):
    """A table drawn cell by cell: each cell's text wraps to its column width
    (no text is cut), rows grow to their tallest cell, pages break between rows.
    widths: fractions of the page width; colours: status colour per row or None."""
    chars_per_unit = 215.0 * 6.0 / fontsize  # characters across the full width at this font size
    line_h = 0.0108 * fontsize / 6.0
    top, bottom, left = 0.905, 0.03, 0.02

    def wrap(cells):
        return [textwrap.wrap(str(c), max(4, int(w * chars_per_unit)), break_long_words=True) or [""]
                for c, w in zip(cells, widths)]

    head_lines = wrap(head)
    pages, fig, y = [], None, 0.0

    def new_page():
        nonlocal fig, y
        fig = _page(title if not pages else title + " (cont.)")
        pages.append(fig)
        y = top
        draw(head_lines, "#dddddd", bold=True)

    def draw(lines, colour, bold=False, status_colour=None):
        nonlocal y
        h = line_h * max(len(c) for c in lines) + 0.004
        x = left
        for j, (cell, w) in enumerate(zip(lines, widths)):
            face = status_colour if (j == 0 and status_colour) else colour
            fig.patches.append(Rectangle((x, y - h), w, h, transform=fig.transFigure, facecolor=face or "white",
                                         edgecolor="#bbbbbb", linewidth=0.3))
            fig.text(x + 0.002, y - 0.002, "\n".join(cell), fontsize=fontsize, va="top", family="DejaVu Sans",
                     weight="bold" if bold or (j == 0 and status_colour) else "normal",
                     color="white" if (j == 0 and status_colour) else "black", linespacing=1.05)
            x += w
        y -= h

    new_page()
    for cells, colour in zip(rows, colours):
        lines = wrap(cells)
        h = line_h * max(len(c) for c in lines) + 0.004
        if y - h < bottom:
            new_page()
        draw(lines, COLOURS.get(colour) if colour in (FAIL, NOT_RUN, MISMATCH, STALE) else None,
             status_colour=STRONG.get(colour))
    return pages


def _summary_pages(rows, title):
    head = ["status", "class", "id", "quantity", "ours", "reference", "unit", "dev.", "dev. %", "tolerance", "gate",
            "run", "source"]
    widths = [0.07, 0.065, 0.17, 0.15, 0.055, 0.055, 0.035, 0.05, 0.045, 0.055, 0.03, 0.065, 0.115]
    if not rows:
        return _wrapped_table_pages(title, ["No reference rows."], [0.96], [], [])
    cells = [[r.status, r.ref.row_class, r.ref.id, r.ref.quantity, fmt(r.ours), fmt(r.ref.value), r.ref.unit,
              fmt(r.dev_abs, 3), fmt(r.dev_pct, 3), tolerance_text(r.ref), "yes" if r.ref.gate else "no",
              f"{r.tier} {r.when}", r.ref.source] for r in rows]
    return _wrapped_table_pages(title, head, widths, cells, [r.status for r in rows])


def _vv20_pages(rows):
    head = ["id", "class", "S (ours)", "D (ref.)", "E", "E %", "u_num", "u_input", "u_D", "u_val", "reading"]
    widths = [0.2, 0.07, 0.06, 0.06, 0.06, 0.045, 0.06, 0.05, 0.05, 0.05, 0.255]
    cells = [[v["id"], v["class"]] + [fmt(v[k], 4) for k in ("S", "D", "E", "E_pct", "u_num", "u_input", "u_D",
                                                              "u_val")] + [v["reading"]] for v in rows]
    return _wrapped_table_pages("Validation and reproduction: E = S - D beside u_num, u_input, u_D (ASME V&V 20)",
                                head, widths, cells, [None] * len(cells))


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
        colour = STRONG[r.status] if r.status in (FAIL, NOT_RUN, MISMATCH, STALE) else "black"
        lines.append((f"{r.status:7s} [{r.ref.row_class}] {r.ref.id}: ours {fmt(r.ours) or '-'} vs {fmt(r.ref.value)} {r.ref.unit}"
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
        lines = []
        for st in report.studies:
            lines.append((st.title, "black"))
            lines.extend((f"   {t}", STRONG[FAIL] if "FAIL" in t.split(":")[0] else "#222222") for t in st.sentences)
            lines.append(("", "black"))
        for fig in _text_pages("Verdict, study by study", lines):
            pdf.savefig(fig)
        for fig in _vv20_pages(report.vv20):
            pdf.savefig(fig)
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

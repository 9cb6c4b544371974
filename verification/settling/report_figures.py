"""The settling study's plots in the validation report (reports/fdem_report/plugins.py):
v(t) per diameter against the GSL integration of the same model, and the terminal velocity
against diameter beside experiment, the paper and Stokes. Reads series_d<D>mm.csv and
terminal.csv (settling_check.cpp)."""
import math

import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, WIDE, key_float, missing, titled
from fdem_report.inputs import StudyResults

S = "str"

TITLE = "Single-particle settling (Sect. 4.1, Table 1)"
SETTLING_SERIES = Schema("settling v(t) for one diameter", (
    C("t_s"), C("v_oneway_mps"), C("v_twoway_mps"), C("v_gsl_mps")))
SETTLING_TERMINAL = Schema("terminal velocity against diameter", (
    C("d_m"), C("vt_exp_mps"), C("vt_paper_mps"), C("vt_stokes_mps"), C("vt_gsl_mps"),
    C("vt_oneway_mps"), C("vt_twoway_mps")), optional=(C("u_num_twoway_mps"),),
    extra_pattern=r"vt_[a-z0-9_.+-]+_mps")

PATTERNS = [
    (r"series_d(?P<d_mm>[0-9]+(?:\.[0-9]+)?)mm\.csv", SETTLING_SERIES, "series_d<D>mm.csv"),
    (r"terminal\.csv", SETTLING_TERMINAL, "terminal.csv"),
]


def settling(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_series, pat_term = (p for p, _, _ in PATTERNS)
    term = res.one(pat_term) if res else None
    series = sorted(res.files(pat_series), key=lambda s: key_float(s, "d_mm")) if res else []
    title = "Settling velocity against time, per diameter: transient (log time) and plateau against GSL"
    if not series:
        plots.append(missing("settling", title, "series_d<D>mm.csv"))
    else:
        n = len(series)
        cols = min(n, 3)
        rows = -(-n // cols)
        fig = Figure(figsize=(3.8 * cols, 5.0 * rows), layout="constrained")
        grid = fig.add_gridspec(2 * rows, cols, height_ratios=[2.2, 1.0] * rows)
        exp = {}
        if term:
            for d, v in zip(term.table.num("d_m"), term.table.num("vt_exp_mps")):
                exp[round(d * 1e3, 6)] = v
        first = None
        for k, s in enumerate(series):
            ax = fig.add_subplot(grid[2 * (k // cols), k % cols])
            axr = fig.add_subplot(grid[2 * (k // cols) + 1, k % cols], sharex=ax)
            first = first or ax
            t = s.table
            d_mm = key_float(s, "d_mm")
            time, gsl = t.num("t_s"), t.num("v_gsl_mps")
            keep = time > 0  # log time axis: the transient of 0.01-0.1 s is visible beside the plateau
            ax.plot(time[keep], gsl[keep], "k--", lw=1.5, label="GSL reference (same model)")
            for col, colour, label in (("v_oneway_mps", "tab:blue", "ours, one-way"),
                                       ("v_twoway_mps", "tab:red", "ours, two-way")):
                v = t.num(col)
                ax.plot(time[keep], v[keep], ".-", color=colour, lw=1, ms=3, label=label)
                with np.errstate(invalid="ignore", divide="ignore"):
                    axr.plot(time[keep], (100 * (v / gsl - 1))[keep], ".-", color=colour, lw=1, ms=3)
            v_exp = exp.get(round(d_mm, 6))
            if v_exp is not None and math.isfinite(v_exp):
                ax.axhline(v_exp, color="tab:green", ls=":", lw=1.5, label="experiment (terminal)")
            ax.set_xscale("log")
            ax.set_title(f"d = {d_mm:g} mm")
            ax.set_ylabel("settling speed [m/s]")
            ax.grid(alpha=0.3, which="both")
            axr.axhline(0, color="k", lw=0.8)
            axr.set_xlabel("t [s] (log; samples every fluid step)")
            axr.set_ylabel("ours / GSL - 1 [%]")
            axr.grid(alpha=0.3, which="both")
        first.legend(fontsize=7)
        fig.suptitle(title)
        plots.append(Plot(title, fig, "Top: speed against time (the first sample is one fluid step in; the "
                                      "smallest grains reach their plateau within it). Bottom: deviation from the "
                                      "GSL integration of the same model at the same times: one-way is the DEM "
                                      "time integration alone, two-way adds the fluid the grain drags along."))
    title = "Terminal velocity against diameter"
    if not term:
        plots.append(missing("settling", title, "terminal.csv"))
    else:
        t = term.table
        d_mm = t.num("d_m") * 1e3
        order = np.argsort(d_mm)
        fig = Figure(figsize=WIDE, layout="constrained")
        ax, axd = fig.subplots(1, 2)
        styles = {"vt_exp_mps": ("experiment (Hallermeier)", "o", "black"),
                  "vt_paper_mps": ("paper, two-way", "s", "tab:blue"),
                  "vt_stokes_mps": ("Stokes", "--", "tab:orange"),
                  "vt_gsl_mps": ("GSL reference", "-", "tab:green"),
                  "vt_oneway_mps": ("ours, one-way", "x", "tab:red"),
                  "vt_twoway_mps": ("ours, two-way", "^", "tab:purple")}
        extra = [c for c in t.columns if c not in styles and c not in ("d_m", "u_num_twoway_mps")]
        for i, c in enumerate(extra):
            styles[c] = (f"{c[3:-4].replace('_', ' ')}", "d", f"C{5 + i}")
        exp = t.num("vt_exp_mps")
        for c, (label, style, colour) in styles.items():
            y = t.num(c)
            ax.plot(d_mm[order], y[order], style, color=colour, label=label, ms=5, lw=1.2,
                    mfc="none" if style == "s" else None)
            if c in ("vt_paper_mps", "vt_gsl_mps", "vt_oneway_mps", "vt_twoway_mps"):
                with np.errstate(invalid="ignore", divide="ignore"):
                    axd.plot(d_mm[order], (100 * (y - exp) / exp)[order], style + "o" if style == "-" else style,
                             color=colour, label=label, ms=5, lw=1, mfc="none" if style == "s" else None)
        ax.set_yscale("log")
        ax.set_xlabel("d [mm]")
        ax.set_ylabel("terminal velocity [m/s] (log scale)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        axd.axhline(0, color="k", lw=0.8)
        with np.errstate(invalid="ignore", divide="ignore"):
            paper_dev = np.abs(100 * (t.num("vt_paper_mps") - exp) / exp)
        worst = float(np.nanmax(paper_dev)) if np.isfinite(paper_dev).any() else None
        if worst is not None:
            for lim in (-worst, worst):
                axd.axhline(lim, color="grey", ls=":", lw=1)
        axd.set_xlabel("d [mm]")
        axd.set_ylabel("deviation from experiment [%]")
        axd.set_title("paper, GSL and ours against experiment"
                      + (f"; dotted: the paper's worst, ±{worst:.3g} %" if worst is not None else ""), fontsize=8)
        axd.grid(alpha=0.3)
        plots.append(titled(fig, title))
    return plots


plots = settling

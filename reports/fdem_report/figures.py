"""What the studies' plots share: the Plot record, the 'not run' note, panel grids,
fitted orders and Pareto fronts, and the plot of a study without its own
(rows_figure). Each study's figures live in its folder,
verification/<study>/report_figures.py (benchmarks/report_figures.py for the
benchmarks), found by plugins.register: each plot is drawn only when its input
file exists; otherwise it is a visible 'not run' note naming the file."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure

from .inputs import SeriesFile, StudyResults

A4_LANDSCAPE = (11.69, 8.27)
WIDE = (11.0, 4.2)


@dataclass
class Plot:
    title: str
    fig: Figure | None
    note: str = ""  # why it was not drawn, or a caption


def missing(study: str, title: str, what: str) -> Plot:
    return Plot(title, None, f"not run: no {study}/{what} in the results")


def one_file(res: StudyResults | None, pattern: str) -> SeriesFile | None:
    """The study's one file matching the pattern; None when the study did not run or wrote none."""
    return res.one(pattern) if res else None


def titled(fig: Figure, title: str, note: str = "") -> Plot:
    """The figure under its title, as a plot of the report."""
    fig.suptitle(title)
    return Plot(title, fig, note)


def log_log(ax, xlabel: str, ylabel: str) -> None:
    """Log-log axes with their labels, the grid and the legend."""
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)


def grid(n: int, max_cols: int = 3, panel=(3.8, 3.2)):
    cols = min(max(n, 1), max_cols)
    rows = max(1, math.ceil(n / cols))
    # At least 6 in wide so the title fits above a few narrow panels.
    fig = Figure(figsize=(max(6.0, panel[0] * cols), panel[1] * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig, axes[:n]


def positive(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    return x[ok], y[ok]


def fitted_order(h, err) -> float | None:
    """Least-squares slope of log(err) against log(h) over all positive points."""
    x, y = positive(h, err)
    if len(x) < 2 or np.ptp(np.log(x)) == 0:
        return None
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def pareto_front(cost, err) -> np.ndarray:
    """Indices of the points no other point beats in both cost and error,
    ordered by cost (the cheapest way to reach each accuracy)."""
    cost, err = np.asarray(cost, float), np.asarray(err, float)
    ok = np.flatnonzero(np.isfinite(cost) & np.isfinite(err))
    order = ok[np.lexsort((err[ok], cost[ok]))]
    front, best = [], math.inf
    for i in order:
        if err[i] < best:
            front.append(i)
            best = err[i]
    return np.array(front, dtype=int)


def key_float(s: SeriesFile, key: str) -> float:
    return float(s.keys[key])


def rows_figure(study: str, rows) -> list[Plot]:
    """For a study without its own plots (a new one, e.g. a dense-regime study
    just landed): every two-sided judged row's deviation in units of its
    tolerance (|x| <= 1 is within it), one-sided rows as ours over the threshold."""
    from .summary import FAIL, PASS, allowed_deviation
    two, one = [], []
    for r in rows:
        if r.ours is None or not math.isfinite(r.ours) or r.ref.tolerance is None:
            continue
        if r.ref.tolerance_kind in ("at_least", "at_most"):
            if r.ref.value != 0:
                one.append((r, r.ours / r.ref.value))
        else:
            width = allowed_deviation(r.ref)
            if width:
                two.append((r, (r.ours - r.ref.value) / width))
    if not two and not one:
        return []
    title = "Our values against the reference rows, in units of each tolerance"
    groups = [g for g in (two, one) if g]
    height = max(2.5, 0.22 * max(len(g) for g in groups) + 1.2)
    fig = Figure(figsize=(11.0, height), layout="constrained")
    axes = fig.subplots(1, len(groups), squeeze=False).ravel()
    colours = {PASS: "tab:green", FAIL: "tab:red"}
    for ax, group in zip(axes, groups):
        group = group[:40]
        y = np.arange(len(group))
        x = np.array([v for _, v in group])
        ax.barh(y, x, color=[colours.get(r.status, "tab:grey") for r, _ in group])
        ax.set_yticks(y)
        ax.set_yticklabels([r.ref.id.removeprefix(study + ".") for r, _ in group], fontsize=6)
        ax.invert_yaxis()
        ax.grid(alpha=0.3, axis="x")
        if group is two:
            ax.axvspan(-1, 1, color="tab:green", alpha=0.08, lw=0)
            ax.set_xlabel("(ours - reference) / tolerance [-]; |x| <= 1 within tolerance")
        else:
            ax.axvline(1.0, color="k", lw=0.8)
            ax.set_xscale("log")
            ax.set_xlabel("ours / threshold (at_least: >= 1 passes; at_most: <= 1)")
    fig.suptitle(title + " (green PASS, red FAIL, grey other)")
    return [Plot(title, fig)]



# Each study's plots, by study name: filled by plugins.register from the study folders.
PLOTTERS: dict = {}

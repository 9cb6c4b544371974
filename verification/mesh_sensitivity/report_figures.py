"""The mesh-sensitivity study's plots in the validation report (reports/fdem_report/plugins.py):
porosity and velocity against time per porosity scheme, and the oscillation amplitudes
against the cell-to-diameter ratio (paper Table 2). Reads series_r<ratio>_<start>_<scheme>.csv
and amplitudes.csv (test_mesh_sensitivity.cpp)."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, key_float, missing, one_file, titled
from fdem_report.inputs import StudyResults

S = "str"

TITLE = "Mesh sensitivity (Sect. 4.2, Table 2)"
MESH_SERIES = Schema("porosity and velocity against time", (C("t_s"), C("porosity"), C("v_mps")))
MESH_AMPLITUDES = Schema("oscillation amplitudes against ratio", (
    C("ratio"), C("start", S), C("scheme", S), C("porosity_amp_pct"), C("velocity_amp_pct")),
    optional=(C("vt_mps"), C("wall_time_s"), C("porosity_amp_paper_pct"),
              C("velocity_amp_paper_pct"), C("porosity_amp_closed_form_pct")))

PATTERNS = [
    (r"series_r(?P<ratio>[0-9]+(?:\.[0-9]+)?)_(?P<start>centred|offset)_(?P<scheme>[a-z0-9]+)\.csv",
     MESH_SERIES, "series_r<ratio>_<start>_<scheme>.csv"),
    (r"amplitudes\.csv", MESH_AMPLITUDES, "amplitudes.csv"),
]


def mesh_sensitivity(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_series, pat_amp = (p for p, _, _ in PATTERNS)
    series = res.files(pat_series) if res else []
    if not series:
        plots.append(missing("mesh_sensitivity", "Porosity and velocity against time",
                              "series_r<ratio>_<start>_<scheme>.csv"))
    for scheme in sorted({s.keys["scheme"] for s in series}):
        title = f"Porosity and velocity against time, porosity scheme '{scheme}'"
        fig = Figure(figsize=(11.0, 6.6), layout="constrained")
        axes = fig.subplots(2, 2, sharex=True)
        mine = sorted((s for s in series if s.keys["scheme"] == scheme), key=lambda s: key_float(s, "ratio"))
        ratios = sorted({key_float(s, "ratio") for s in mine})
        import matplotlib
        cmap = matplotlib.colormaps["viridis"]
        for s in mine:
            col = 0 if s.keys["start"] == "centred" else 1
            r = key_float(s, "ratio")
            colour = cmap(ratios.index(r) / max(1, len(ratios) - 1) * 0.9)
            axes[0, col].plot(s.table.num("t_s"), s.table.num("porosity"), color=colour, lw=1, label=f"ratio {r:g}")
            axes[1, col].plot(s.table.num("t_s"), s.table.num("v_mps"), color=colour, lw=1, label=f"ratio {r:g}")
        for col, start in enumerate(("centred", "offset")):
            axes[0, col].set_title(f"{start} start")
            axes[0, col].set_ylabel("porosity of the particle's element [-]")
            axes[1, col].set_ylabel("settling speed [m/s]")
            axes[1, col].set_xlabel("t [s]")
            for a in axes[:, col]:
                a.grid(alpha=0.3)
            if axes[0, col].lines:
                axes[0, col].legend(fontsize=7)
            else:
                axes[0, col].text(0.5, 0.5, f"not run: no {start} series", transform=axes[0, col].transAxes, ha="center")
        plots.append(titled(fig, title))
    title = "Oscillation amplitude against cell-to-diameter ratio"
    if not (amp := one_file(res, pat_amp)):
        plots.append(missing("mesh_sensitivity", title, "amplitudes.csv"))
        return plots
    t = amp.table
    has_wall = t.has("wall_time_s")
    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    axes = fig.subplots(1, 3 if has_wall else 2)
    ratio = t.num("ratio")
    groups = sorted({(r["scheme"], r["start"]) for r in t.rows})
    for scheme, start in groups:
        sel = np.array([(r["scheme"], r["start"]) == (scheme, start) for r in t.rows])
        o = np.argsort(ratio[sel])
        style = "-o" if start == "offset" else ":o"
        for ax, c in zip(axes, ("porosity_amp_pct", "velocity_amp_pct")):
            ax.plot(ratio[sel][o], t.num(c)[sel][o], style, ms=4, lw=1, label=f"ours, {scheme}, {start}")
        if has_wall:
            axes[2].plot(ratio[sel][o], t.num("wall_time_s")[sel][o], style, ms=4, lw=1, label=f"{scheme}, {start}")
    for ax, c, label in ((axes[0], "porosity_amp_paper_pct", "paper"), (axes[1], "velocity_amp_paper_pct", "paper"),
                         (axes[0], "porosity_amp_closed_form_pct", "closed form, 5-tet split")):
        if t.has(c):
            y = t.num(c)
            ok = np.isfinite(y)
            o = np.argsort(ratio[ok])
            ax.plot(ratio[ok][o], y[ok][o], "ks" if label == "paper" else "k+", ms=7, mfc="none", label=label)
    axes[0].set_ylabel("porosity amplitude, peak-to-peak / mean [%]")
    axes[1].set_ylabel("velocity amplitude, peak-to-peak / mean [%]")
    for ax in axes[:2]:
        ax.set_yscale("log")
    if has_wall:
        axes[2].set_ylabel("wall time [s]")
        axes[2].set_title("what the scheme costs", fontsize=9)
    for ax in axes:
        ax.set_xlabel("cell size / diameter")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=6)
    fig.suptitle(title + " (zero amplitudes are not drawn on the log axes)")
    plots.append(Plot(title, fig))
    return plots


plots = mesh_sensitivity

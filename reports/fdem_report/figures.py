"""One function per study returning its plots. Each plot is drawn only when its
input file exists; otherwise it is a visible 'not run' note naming the file."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from matplotlib.figure import Figure

from . import formats
from .inputs import SeriesFile, StudyResults

A4_LANDSCAPE = (11.69, 8.27)
WIDE = (11.0, 4.2)


@dataclass
class Plot:
    title: str
    fig: Figure | None
    note: str = ""  # why it was not drawn, or a caption


def _missing(study: str, title: str, what: str) -> Plot:
    return Plot(title, None, f"not run: no {study}/{what} in the results")


def _grid(n: int, max_cols: int = 3, panel=(3.8, 3.2)):
    cols = min(max(n, 1), max_cols)
    rows = max(1, math.ceil(n / cols))
    # At least 6 in wide so the title fits above a few narrow panels.
    fig = Figure(figsize=(max(6.0, panel[0] * cols), panel[1] * rows + 0.6), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax in axes[n:]:
        ax.set_visible(False)
    return fig, axes[:n]


def _positive(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    return x[ok], y[ok]


def fitted_order(h, err) -> float | None:
    """Least-squares slope of log(err) against log(h) over all positive points."""
    x, y = _positive(h, err)
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


def _key_float(s: SeriesFile, key: str) -> float:
    return float(s.keys[key])


# ---------------------------------------------------------------------------
def settling(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_series, pat_term = (p for p, _, _ in formats.PATTERNS["settling"])
    term = res.one(pat_term) if res else None
    series = sorted(res.files(pat_series), key=lambda s: _key_float(s, "d_mm")) if res else []
    title = "Settling velocity against time, per diameter: transient (log time) and plateau against GSL"
    if not series:
        plots.append(_missing("settling", title, "series_d<D>mm.csv"))
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
            d_mm = _key_float(s, "d_mm")
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
        plots.append(_missing("settling", title, "terminal.csv"))
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
        fig.suptitle(title)
        plots.append(Plot(title, fig))
    return plots


# ---------------------------------------------------------------------------
def mesh_sensitivity(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_series, pat_amp = (p for p, _, _ in formats.PATTERNS["mesh_sensitivity"])
    series = res.files(pat_series) if res else []
    if not series:
        plots.append(_missing("mesh_sensitivity", "Porosity and velocity against time",
                              "series_r<ratio>_<start>_<scheme>.csv"))
    for scheme in sorted({s.keys["scheme"] for s in series}):
        title = f"Porosity and velocity against time, porosity scheme '{scheme}'"
        fig = Figure(figsize=(11.0, 6.6), layout="constrained")
        axes = fig.subplots(2, 2, sharex=True)
        mine = sorted((s for s in series if s.keys["scheme"] == scheme), key=lambda s: _key_float(s, "ratio"))
        ratios = sorted({_key_float(s, "ratio") for s in mine})
        import matplotlib
        cmap = matplotlib.colormaps["viridis"]
        for s in mine:
            col = 0 if s.keys["start"] == "centred" else 1
            r = _key_float(s, "ratio")
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
        fig.suptitle(title)
        plots.append(Plot(title, fig))
    title = "Oscillation amplitude against cell-to-diameter ratio"
    amp = res.one(pat_amp) if res else None
    if not amp:
        plots.append(_missing("mesh_sensitivity", title, "amplitudes.csv"))
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


# ---------------------------------------------------------------------------
def channel(res: StudyResults | None) -> list[Plot]:
    title = "Outlet velocity profiles with the fitted near-bed slopes"
    pat_prof, pat_slopes = (p for p, _, _ in formats.PATTERNS["channel"])
    profiles = {s.keys["case"]: s for s in res.files(pat_prof)} if res else {}
    if not profiles:
        return [_missing("channel", title, "profile_wall.csv / profile_bed.csv")]
    slopes = res.one(pat_slopes)
    fig = Figure(figsize=(7.5, 5.5), layout="constrained")
    ax = fig.subplots()
    colours = {"wall": "tab:blue", "bed": "tab:brown"}
    names = {"wall": "no-slip wall", "bed": "settled bed"}
    for case, s in sorted(profiles.items()):
        ax.plot(s.table.num("u_mps") * 1e3, s.table.num("z_m") * 1e3, "o-", ms=3, lw=1,
                color=colours[case], label=f"outlet profile, {names[case]}")
    notes = []
    if slopes:
        for r in slopes.table.rows:
            case = str(r["case"])
            z = np.linspace(r["z_from_m"], r["z_to_m"], 2)
            u = r["u_at_z_from_mps"] + r["dudz_1ps"] * (z - r["z_from_m"])
            paper = r.get("slope_paper_deg")
            label = f"fit, {names.get(case, case)}: {r['slope_deg']:.3g} deg"
            if paper is not None and math.isfinite(paper):
                label += f" (paper {paper:.3g} deg)"
            ax.plot(u * 1e3, z * 1e3, "--", lw=2.5, color=colours.get(case, "k"), alpha=0.7, label=label)
            bed_top = r.get("bed_top_m")
            if bed_top is not None and math.isfinite(bed_top):
                ax.axhline(bed_top * 1e3, color=colours.get(case, "k"), ls=":", lw=1, label=f"bed top ({case})")
        by_case = {str(r["case"]): r["slope_deg"] for r in slopes.table.rows}
        if "wall" in by_case and "bed" in by_case and by_case["wall"]:
            ax.set_title(f"slope ratio bed / wall = {by_case['bed'] / by_case['wall']:.3g} (paper 1.52)", fontsize=9)
    else:
        notes.append("fitted slopes not run: no channel/slopes.csv")
    ax.set_xlabel("streamwise velocity u [mm/s]")
    ax.set_ylabel("height z [mm]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle(title)
    return [Plot(title, fig, "; ".join(notes))]


# ---------------------------------------------------------------------------
def plume(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_metrics, pat_particles, pat_fluid = (p for p, _, _ in formats.PATTERNS["plume"])
    title = "Dome metrics against time, two-way and one-way"
    metrics = res.files(pat_metrics) if res else []
    if not metrics:
        plots.append(_missing("plume", title, "metrics_<mode>.csv"))
    else:
        cols = [("front_depth_m", "cloud front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
                ("radial_spread_m", "radial spread (2nd moment) [mm]", 1e3), ("dome_shape", "dome shape, least squares [-]", 1.0),
                ("peak_fluid_speed_mps", "peak fluid speed [mm/s]", 1e3)]
        cols = [c for c in cols if any(m.table.has(c[0]) for m in metrics)]
        fig, axes = _grid(len(cols), 3, (3.7, 3.0))
        styles = {"twoway": ("tab:red", "-"), "oneway_f2p": ("tab:blue", "--"), "oneway_p2f": ("tab:green", ":")}
        for ax, (c, label, scale) in zip(axes, cols):
            for m in sorted(metrics, key=lambda s: list(formats.PLUME_MODES).index(s.keys["mode"])):
                if m.table.has(c):
                    colour, ls = styles[m.keys["mode"]]
                    ax.plot(m.table.num("t_s"), m.table.num(c) * scale, ls, color=colour, lw=1.4,
                            label=formats.PLUME_MODES[m.keys["mode"]])
            ax.set_xlabel("t [s]")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.suptitle(title)
        plots.append(Plot(title, fig))
    for pattern, what, draw, tpl in ((pat_particles, "grains, side view (x-z)", _plume_particles,
                                      "particles_<mode>_t<T>s.csv"),
                                     (pat_fluid, "fluid speed on the mid-plane y = W/2", _plume_fluid,
                                      "fluid_speed_<mode>_t<T>s.csv")):
        files = res.files(pattern) if res else []
        if not files:
            plots.append(_missing("plume", f"Snapshots: {what}", tpl))
            continue
        for mode in [m for m in formats.PLUME_MODES if any(f.keys["mode"] == m for f in files)]:
            snaps = sorted((f for f in files if f.keys["mode"] == mode), key=lambda f: _key_float(f, "t_s"))[:6]
            title = f"Snapshots: {what}, {formats.PLUME_MODES[mode]}"
            plots.append(Plot(title, draw(snaps, title)))
    return plots


def plume_main(res: StudyResults | None) -> list[Plot]:
    """The main job's plume beside the full one: the same metrics against time,
    the full run's (results folder plume/, tier full) dashed where it exists."""
    pat_metrics = formats.pattern("plume_main", "metrics_<mode>.csv")
    title = "Main-job plume (contacts off, 10 subcycles) against the full plume"
    metrics = res.files(pat_metrics) if res else []
    if not metrics:
        return [_missing("plume_main", title, "metrics_<mode>.csv")]
    full = []
    sibling = res.folder.parent / "plume"
    if (sibling / "meta.json").is_file():
        from .inputs import load_study
        other = load_study(sibling, "plume")
        if other.meta and other.meta.get("tier") == "full":
            full = other.files(formats.pattern("plume", "metrics_<mode>.csv"))
    cols = [("front_depth_m", "cloud front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
            ("radial_spread_m", "radial spread (2nd moment) [mm]", 1e3), ("dome_shape", "dome shape, least squares [-]", 1.0),
            ("peak_fluid_speed_mps", "peak fluid speed [mm/s]", 1e3)]
    cols = [c for c in cols if any(m.table.has(c[0]) for m in metrics)]
    fig, axes = _grid(len(cols), 3, (3.7, 3.0))
    colours = {"twoway": "tab:red", "oneway_f2p": "tab:blue", "oneway_p2f": "tab:green"}
    for ax, (c, label, scale) in zip(axes, cols):
        for runs, ls, lw, who in ((metrics, "-", 1.4, "main"), (full, "--", 1.0, "full")):
            for m in runs:
                if m.table.has(c) and m.keys["mode"] != "oneway_p2f":
                    ax.plot(m.table.num("t_s"), m.table.num(c) * scale, ls, color=colours[m.keys["mode"]], lw=lw,
                            label=f"{formats.PLUME_MODES[m.keys['mode']]}, {who}")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.suptitle(title + ("" if full else " (no full run in these results: main only)"))
    return [Plot(title, fig)]


def _plume_particles(snaps: list[SeriesFile], title: str) -> Figure:
    fig, axes = _grid(len(snaps), 6, (1.9, 4.2))
    xs = np.concatenate([s.table.num("x_m") for s in snaps]) * 1e3
    zs = np.concatenate([s.table.num("z_m") for s in snaps]) * 1e3
    for ax, s in zip(axes, snaps):
        d = s.table.num("d_m")
        size = 2.0 * (d / np.nanmean(d)) ** 2 if len(d) else 1.0
        ax.scatter(s.table.num("x_m") * 1e3, s.table.num("z_m") * 1e3, s=size, c="saddlebrown",
                   linewidths=0, alpha=0.6, rasterized=True)
        ax.set_title(f"t = {_key_float(s, 't_s'):g} s ({len(d)} grains)", fontsize=8)
        ax.set_xlabel("x [mm]")
        if len(xs):
            ax.set_xlim(np.nanmin(xs), np.nanmax(xs))
            ax.set_ylim(np.nanmin(zs), np.nanmax(zs))
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("z [mm]")
    fig.suptitle(title)
    return fig


def grid_from_long(s: SeriesFile):
    """Reshape x_m, z_m, speed_mps rows into a full regular grid, or raise."""
    from .csvio import InputError
    x, z, v = s.table.num("x_m"), s.table.num("z_m"), s.table.num("speed_mps")
    ux, uz = np.unique(x), np.unique(z)
    if len(ux) * len(uz) != len(x) or len(ux) < 2 or len(uz) < 2:
        raise InputError(s.table.path, None, f"not a full regular grid: {len(x)} rows for {len(ux)} x and "
                         f"{len(uz)} z values (need every (x, z) pair once, at least 2 x 2)")
    grid = np.full((len(uz), len(ux)), np.nan)
    ix, iz = np.searchsorted(ux, x), np.searchsorted(uz, z)
    grid[iz, ix] = v
    if np.isnan(grid).sum() != np.isnan(v).sum():
        raise InputError(s.table.path, None, "not a full regular grid: some (x, z) pair appears twice")
    return ux, uz, grid


def _plume_fluid(snaps: list[SeriesFile], title: str) -> Figure:
    grids = [grid_from_long(s) for s in snaps]
    vmax = max(float(np.nanmax(g[2])) if np.isfinite(g[2]).any() else 0.0 for g in grids) * 1e3 or 1.0
    fig, axes = _grid(len(snaps), 6, (1.9, 4.2))
    mesh = None
    for ax, s, (ux, uz, g) in zip(axes, snaps, grids):
        mesh = ax.pcolormesh(ux * 1e3, uz * 1e3, g * 1e3, shading="nearest", vmin=0, vmax=vmax, cmap="viridis")
        ax.set_title(f"t = {_key_float(s, 't_s'):g} s", fontsize=8)
        ax.set_xlabel("x [mm]")
        ax.set_aspect("equal")
    axes[0].set_ylabel("z [mm]")
    if mesh is not None:
        fig.colorbar(mesh, ax=list(axes), label="|u| [mm/s]", shrink=0.8)
    fig.suptitle(title)
    return fig


# ---------------------------------------------------------------------------
def fluid(res: StudyResults | None) -> list[Plot]:
    title = "Convergence under mesh refinement"
    conv = res.one(formats.pattern("fluid", "convergence.csv")) if res else None
    if not conv:
        return [_missing("fluid", title, "convergence.csv")]
    t = conv.table
    cases = sorted({str(r["case"]) for r in t.rows})
    fig, axes = _grid(len(cases), 3, (3.8, 3.4))
    h, err = t.num("h_m"), t.num("error")
    expected = t.num("expected_order") if t.has("expected_order") else np.full(len(h), np.nan)
    for ax, case in zip(axes, cases):
        for q in sorted({str(r["quantity"]) for r in t.rows if r["case"] == case}):
            sel = np.array([r["case"] == case and r["quantity"] == q for r in t.rows])
            o = np.argsort(h[sel])
            p = fitted_order(h[sel], err[sel])
            hs, es = _positive(h[sel][o], err[sel][o])
            # The finest pair's order too: the table's order rows name a mesh pair (e.g. 8 -> 12
            # cells), which differs from the fit over all h when the error is not yet asymptotic.
            p2 = math.log(es[1] / es[0]) / math.log(hs[1] / hs[0]) if len(hs) >= 2 and hs[1] != hs[0] else None
            label = q if p is None else (f"{q}: order {p:.2f} (fit, all h)"
                                         + (f", {p2:.2f} (finest pair)" if p2 is not None and len(hs) > 2 else ""))
            line, = ax.plot(h[sel][o], err[sel][o], "o-", ms=4, label=label)
            exp_q = expected[sel][np.isfinite(expected[sel])]
            hx, ey = _positive(h[sel][o], err[sel][o])
            if len(exp_q) and len(hx):
                ref = ey[0] * (hx / hx[0]) ** exp_q[0]
                ax.plot(hx, ref, ":", color=line.get_color(), lw=1, label=f"slope {exp_q[0]:g} (expected)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("h [m]")
        ax.set_ylabel("error")
        ax.set_title(case, fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.suptitle(title + " (order: least-squares fit over all h, and between the two finest meshes)")
    return [Plot(title, fig, "Two orders per line: the least-squares slope over every mesh, and the slope between "
                             "the two finest; the summary table's order rows are the slope between the mesh pair "
                             "they name, so they match neither when the error is not yet in its asymptotic range.")]


# ---------------------------------------------------------------------------
def dem(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_rest, pat_energy = (p for p, _, _ in formats.PATTERNS["dem"])
    title = "Restitution and contact time against damping ratio"
    rest = res.one(pat_rest) if res else None
    if not rest:
        plots.append(_missing("dem", title, "restitution.csv"))
    else:
        t = rest.table
        has_tc = t.has("tc_analytic_s") and t.has("tc_measured_s")
        fig = Figure(figsize=WIDE if has_tc else (6.0, 4.2), layout="constrained")
        axes = np.atleast_1d(fig.subplots(1, 2 if has_tc else 1))
        zeta = t.num("zeta")
        for case in sorted({str(r["case"]) for r in t.rows}):
            sel = np.array([r["case"] == case for r in t.rows])
            o = np.argsort(zeta[sel])
            pairs = [(axes[0], "e_analytic", "e_measured")]
            if has_tc:
                pairs.append((axes[1], "tc_analytic_s", "tc_measured_s"))
            for ax, ca, cm in pairs:
                line, = ax.plot(zeta[sel][o], t.num(ca)[sel][o], "-", lw=1, label=f"analytic, {case}")
                ax.plot(zeta[sel][o], t.num(cm)[sel][o], "o", mfc="none", color=line.get_color(), label=f"ours, {case}")
        axes[0].set_ylabel("coefficient of restitution e [-]")
        if has_tc:
            axes[1].set_ylabel("contact time [s]")
        for ax in axes:
            ax.set_xlabel("damping ratio zeta [-]")
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
        fig.suptitle(title)
        plots.append(Plot(title, fig))
    title = "Energy error against DEM step (no damping, no friction)"
    energy = res.one(pat_energy) if res else None
    if not energy:
        plots.append(_missing("dem", title, "energy.csv"))
    else:
        t = energy.table
        fig = Figure(figsize=(6.0, 4.2), layout="constrained")
        ax = fig.subplots()
        cases = sorted({str(r.get("case", "")) for r in t.rows})
        for case in cases:
            sel = np.array([str(r.get("case", "")) == case for r in t.rows])
            dt, e = t.num("dt_s")[sel], np.abs(t.num("energy_error_rel")[sel])
            o = np.argsort(dt)
            p = fitted_order(dt, e)
            label = (case + ": " if case else "") + (f"order {p:.2f}" if p is not None else "")
            ax.plot(dt[o], e[o], "o-", ms=4, label=label or None)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("DEM step dt [s]")
        ax.set_ylabel("|relative energy error| [-]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        fig.suptitle(title)
        plots.append(Plot(title, fig))
    return plots


# ---------------------------------------------------------------------------
def benchmarks(res: StudyResults | None) -> list[Plot]:
    return _accuracy_and_trends(res) + [_plume_sweep(res), _scaling(res)]


def _plume_sweep(res: StudyResults | None) -> Plot:
    """Plume metrics at the end time against grain count, one line per mesh
    size, and the wall time of each run (benchmarks/sweeps/plume_sweep.cpp)."""
    title = "Plume metrics against grain count and mesh size (reduced plume, two-way)"
    f = res.one(formats.pattern("benchmarks", "plume_sweep.csv")) if res else None
    if not f:
        return _missing("benchmarks", title, "plume_sweep.csv")
    t = f.table
    panels = [("front_depth_m", "front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
              ("radial_spread_m", "radial spread [mm]", 1e3)]
    panels += [(c, lab, k) for c, lab, k in (("dome_shape", "dome shape, least squares [-]", 1.0),
                                             ("peak_fluid_speed_mps", "peak fluid speed [m/s]", 1.0))
               if t.has(c)]
    panels.append(("wall_time_s", "wall time [s]", 1.0))
    fig, axes = _grid(len(panels), 3, (3.8, 3.0))
    grains, cell = t.num("grains"), t.num("cell_m")
    cells = sorted({float(c) for c in cell if math.isfinite(c)}, reverse=True)
    for ax, (col, label, k) in zip(axes, panels):
        y = t.num(col) * k
        for c in cells:
            sel = np.flatnonzero(cell == c)
            o = sel[np.argsort(grains[sel])]
            ax.plot(grains[o], y[o], "o-", ms=4, lw=1, label=f"cell {1e3 * c:.1f} mm")
        ax.set_xscale("log")
        if col == "wall_time_s" and (y[np.isfinite(y)] > 0).all():
            ax.set_yscale("log")
        ax.set_xlabel("grains")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    modes = sorted({str(r["mode"]) for r in t.rows})
    ends = sorted({float(r["t_s"]) for r in t.rows})
    fig.suptitle(f"{title}; mode {', '.join(modes)}, t = {', '.join(f'{e:g}' for e in ends)} s")
    note = ("Grain volume fraction held; the finest mesh and the most grains are the reference each setting "
            "is read against. Wall times are of one thread on the machine that ran the sweep.")
    return Plot(title, fig, note)


def _scaling(res: StudyResults | None) -> Plot:
    """Cost per item-step against problem size, fitted exponent of the time per
    step in the legend, and the two-thread speed-up (benchmarks/dem/scaling.py)."""
    title = "Cost against problem size: fitted exponent, one against two threads"
    f = res.one(formats.pattern("benchmarks", "scaling.csv")) if res else None
    if not f:
        return _missing("benchmarks", title, "scaling.csv")
    t = f.table
    case = np.array([str(r["case"]) for r in t.rows])
    size, threads, sec = t.num("size"), t.num("threads"), t.num("seconds_per_step")
    fig = Figure(figsize=WIDE, layout="constrained")
    ax_cost, ax_speed = fig.subplots(1, 2)
    for c in dict.fromkeys(case):
        for th in sorted({float(x) for x in threads[case == c]}):
            sel = np.flatnonzero((case == c) & (threads == th))
            o = sel[np.argsort(size[sel])]
            p = fitted_order(size[o], sec[o])
            label = f"{c}, {th:g} thread{'s' if th != 1 else ''}" + (f": N^{p:.2f}" if p is not None else "")
            ax_cost.plot(size[o], 1e9 * sec[o] / size[o], "o-" if th == 1 else "s--", ms=4, lw=1, label=label)
        one = {float(size[i]): sec[i] for i in np.flatnonzero((case == c) & (threads == 1))}
        two = {float(size[i]): sec[i] for i in np.flatnonzero((case == c) & (threads == 2))}
        common = sorted(set(one) & set(two))
        if common:
            ax_speed.plot(common, [one[n] / two[n] for n in common], "o-", ms=4, lw=1, label=c)
    ax_cost.set_xscale("log")
    ax_cost.set_yscale("log")
    ax_cost.set_xlabel("problem size N (particles or tetrahedra)")
    ax_cost.set_ylabel("time per step / N [ns]")
    ax_cost.grid(alpha=0.3, which="both")
    ax_cost.legend(fontsize=7)
    ax_speed.axhline(2.0, color="grey", lw=0.8, ls=":")
    ax_speed.axhline(1.0, color="grey", lw=0.8)
    ax_speed.set_xscale("log")
    ax_speed.set_xlabel("problem size N")
    ax_speed.set_ylabel("speed-up, 2 threads over 1 [-]")
    ax_speed.grid(alpha=0.3, which="both")
    if ax_speed.lines[2:]:
        ax_speed.legend(fontsize=7)
    else:
        ax_speed.text(0.5, 0.5, "no size with both 1- and 2-thread rows", transform=ax_speed.transAxes,
                      ha="center", va="center", fontsize=9, color="grey")
    fig.suptitle(title)
    note = "Exponent: least-squares slope of log(time per step) against log(N); 1 = linear cost."
    return Plot(title, fig, note)


def _accuracy_and_trends(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_cost = formats.pattern("benchmarks", "accuracy_cost.csv")
    pat_hist = formats.pattern("benchmarks", "history.csv")
    title = "What accuracy costs: error against wall time, Pareto front marked"
    cost = res.one(pat_cost) if res else None
    if not cost:
        plots.append(_missing("benchmarks", title, "accuracy_cost.csv"))
    else:
        t = cost.table
        sweeps = list(dict.fromkeys(str(r["sweep"]) for r in t.rows))
        fig, axes = _grid(len(sweeps), 3, (3.8, 3.4))
        remarks = []
        for ax, sweep in zip(axes, sweeps):
            idx = np.array([i for i, r in enumerate(t.rows) if r["sweep"] == sweep])
            w, e = t.num("wall_time_s")[idx], t.num("error")[idx]
            finite = e[np.isfinite(e)]
            if len(idx) < 5:
                remarks.append(f"{sweep}: only {len(idx)} settings (a front needs at least 5 to show a trade-off; "
                               "the nightly sweep has more)")
            elif len(finite) and finite.max() <= 1.01 * finite.min():
                remarks.append(f"{sweep}: the error does not change over the sweep ({finite.min():.3g}-"
                               f"{finite.max():.3g}): this setting costs time and buys no accuracy")
            ax.plot(w, e, "o", color="tab:blue", ms=5, label="setting")
            for i, k in enumerate(idx):
                ax.annotate(str(t.rows[k]["setting"]), (w[i], e[i]), fontsize=6, xytext=(3, 3),
                            textcoords="offset points")
            front = pareto_front(w, e)
            if len(front):
                ax.step(w[front], e[front], "-", where="post", color="tab:red", lw=1.2)
                ax.plot(w[front], e[front], "o", mfc="none", mec="tab:red", ms=9, label="Pareto front")
            kinds = {str(t.rows[k].get("error_kind", "")) for k in idx} - {""}
            positive = w[np.isfinite(w) & (w > 0)]
            if len(positive) and positive.max() > 3.0 * positive.min():  # a narrower span reads better linear
                ax.set_xscale("log")
            if (e[np.isfinite(e)] > 0).all():
                ax.set_yscale("log")
            ax.set_xlabel("wall time [s]")
            ax.set_ylabel("error" + (f" ({'; '.join(sorted(kinds))})" if kinds else ""), fontsize=8)
            ax.set_title(f"sweep: {sweep}", fontsize=9)
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=7)
        fig.suptitle(title)
        plots.append(Plot(title, fig, "; ".join(remarks)))
    title = "Benchmark trends against commit"
    hist = res.one(pat_hist) if res else None
    if not hist:
        plots.append(_missing("benchmarks", title, "history.csv (or --history)"))
        return plots
    t = hist.table
    commits = list(dict.fromkeys(str(r["commit"]) for r in t.rows))
    names = list(dict.fromkeys(str(r["benchmark"]) for r in t.rows))
    # The benchmarks with the longest history first (a trend needs points),
    # then in the history's order.
    history_length = {n: len({str(r["commit"]) for r in t.rows if r["benchmark"] == n}) for n in names}
    shown = sorted(names, key=lambda n: -history_length[n])[:12]
    fig, axes = _grid(len(shown), 3, (3.8, 2.8))
    for ax, name in zip(axes, shown):
        rows = [r for r in t.rows if r["benchmark"] == name]
        x = np.array([commits.index(str(r["commit"])) for r in rows])
        y = np.array([r["value"] for r in rows], dtype=float)
        ax.plot(x, y, "o-", ms=3, lw=1)
        band = [r.get("noise_band_rel") for r in rows]
        if band and band[-1] is not None and math.isfinite(band[-1]) and len(y):
            med = float(np.nanmedian(y))
            ax.axhspan(med * (1 - band[-1]), med * (1 + band[-1]), color="grey", alpha=0.15, lw=0, label="noise band")
        reg = np.array([r.get("regression") is not None and math.isfinite(r["regression"]) and r["regression"] != 0
                        for r in rows], dtype=bool)
        if reg.any():
            ax.plot(x[reg], y[reg], "x", color="red", ms=9, mew=2, label="regression")
            ax.legend(fontsize=6)
        ax.set_title(f"{name} [{rows[0]['unit']}]", fontsize=8)
        ax.set_xticks(range(len(commits)))
        ax.set_xticklabels([c[:7] for c in commits], rotation=60, fontsize=6)
        ax.grid(alpha=0.3)
    note = (f"{len(t.rows)} measurements of {len(names)} benchmarks over {len(commits)} commits "
            f"({str(t.rows[0]['date'])[:10]} to {str(t.rows[-1]['date'])[:10]}); the {len(shown)} with the longest "
            f"history drawn" + (f", {len(names) - len(shown)} more not drawn" if len(names) > len(shown) else ""))
    fig.suptitle(title)
    plots.append(Plot(title, fig, note))
    return plots


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


PLOTTERS = {"settling": settling, "mesh_sensitivity": mesh_sensitivity, "channel": channel, "plume": plume,
            "plume_main": plume_main,
            "fluid": fluid, "dem": dem, "benchmarks": benchmarks}

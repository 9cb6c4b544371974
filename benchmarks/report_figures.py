"""The benchmarks' plots in the validation report (reports/fdem_report/plugins.py): what
accuracy costs (error against wall time with the Pareto front), the benchmark trends against
commit, the plume sweep, the cost scaling, the DEM against LIGGGHTS and the plume's real DEM
workload. Reads accuracy_cost.csv, history.csv, plume_sweep.csv, scaling.csv,
dem_vs_liggghts.csv and plume_dem_workload.csv (formats.py: the benchmark tools read the same
schemas)."""
import math

import numpy as np
from matplotlib.figure import Figure

from fdem_report import formats
from fdem_report.figures import Plot, WIDE, fitted_order, grid, log_log, missing, one_file, pareto_front, titled
from fdem_report.inputs import StudyResults

TITLE = "What accuracy costs; benchmark trends"


# The DEM's speed goals against LIGGGHTS 3.8 (issue 19, item 2b; the project's
# aims): the free-falling block (scene P, contact-free) 4x, the settled bed
# (scene B) 3x its particle-steps/s, on 1 and 2 threads; and (item 2a) the
# plume's DEM without drag at 0.8 of scene P's rate.
LIGGGHTS_GOALS = {"P": 4.0, "B": 3.0}
PLUME_DRY_OVER_P_GOAL = 0.8


def benchmarks(res: StudyResults | None) -> list[Plot]:
    return _accuracy_and_trends(res) + [_plume_sweep(res), _scaling(res), _dem_vs_liggghts(res),
                                        _plume_dem_workload(res)]


def _dem_vs_liggghts(res: StudyResults | None) -> Plot:
    """fdem's particle-steps/s over LIGGGHTS's on the anchors' scenes, both codes
    run in one session (benchmarks/dem/side_by_side.py), against the goals."""
    title = "DEM against LIGGGHTS 3.8, side by side: particle-steps/s ratio"
    if not (f := one_file(res, formats.pattern("benchmarks", "dem_vs_liggghts.csv"))):
        return missing("benchmarks", title, "dem_vs_liggghts.csv")
    t = f.table
    scenes = list(dict.fromkeys(str(r["scene"]) for r in t.rows))
    threads = sorted({float(x) for x in t.num("threads") if math.isfinite(x)})
    fig = Figure(figsize=(max(6.0, 2.2 * len(scenes) + 2.0), 3.6), layout="constrained")
    ax = fig.subplots()
    width = 0.8 / max(1, len(threads))
    for k, th in enumerate(threads):
        for x, scene in enumerate(scenes):
            rows = [r for r in t.rows if str(r["scene"]) == scene and float(r["threads"]) == th]
            if not rows:
                continue
            ratio = float(rows[-1]["ratio"])
            pos = x - 0.4 + width * (k + 0.5)
            ax.bar(pos, ratio, width * 0.9, color=f"C{k}", label=f"{th:g} thread{'s' if th != 1 else ''}"
                   if x == 0 else None)
            ax.annotate(f"{ratio:.3g}x", (pos, ratio), ha="center", va="bottom", fontsize=7)
    for x, scene in enumerate(scenes):
        if scene in LIGGGHTS_GOALS:
            ax.hlines(LIGGGHTS_GOALS[scene], x - 0.45, x + 0.45, colors="tab:red", linestyles="--", lw=1.2,
                      label="goal" if x == 0 else None)
    ax.axhline(1.0, color="grey", lw=0.8)
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels([{"P": "P: falling block, no contacts", "B": "B: settled bed"}.get(sc, sc) for sc in scenes],
                       fontsize=8)
    ax.set_ylabel("fdem / LIGGGHTS particle-steps/s [-]")
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=7)
    fig.suptitle(title)
    spreads = [f"{str(r['scene'])}/{float(r['threads']):g}: fdem {100 * float(r['fdem_spread']):.0f} %, "
               f"LIGGGHTS {100 * float(r['liggghts_spread']):.0f} %" for r in t.rows
               if r.get("fdem_spread") is not None and r.get("liggghts_spread") is not None]
    dates = sorted({str(r["date"]) for r in t.rows if r.get("date")})
    note = ("Both codes on the same machine in one run, shuffled, medians of the repetitions"
            + (f" ({', '.join(dates)})" if dates else "") + "; a ratio is only as good as the two spreads "
            "(max - min over median)" + (f": {'; '.join(spreads)}" if spreads else "") + ". Goals: issue 19.")
    return Plot(title, fig, note)


# The plume's DEM phases as plume_workload.py names them (shares of the engine's time).
PLUME_PHASES = [("integration_share", "integration"), ("neighbour_build_share", "list rebuilds"),
                ("pairs_share", "pair contacts"), ("walls_share", "walls"), ("body_force_share", "body force"),
                ("external_share", "drag (subcycle)")]


def _plume_dem_workload(res: StudyResults | None) -> Plot:
    """The real coupled plume's DEM from checkpoints (benchmarks/dem/plume_workload.py):
    where its time goes, its rate without drag over scene P's, and its two
    streaming phases over what the machine needs merely to stream their bytes."""
    title = "The plume's DEM from checkpoints: where the time goes, against scene P and the streaming floors"
    if not (f := one_file(res, formats.pattern("benchmarks", "plume_dem_workload.csv"))):
        return missing("benchmarks", title, "plume_dem_workload.csv")
    t = f.table
    fig, (ax_share, ax_rate, ax_floor) = grid(3, 3, (4.0, 3.8))
    checkpoint, threads = t.num("checkpoint_s"), t.num("threads")
    labels = [f"{c:g} s, {th:g} thr" for c, th in zip(checkpoint, threads)]
    left = np.zeros(len(t.rows))
    for k, (col, name) in enumerate((c, n) for c, n in PLUME_PHASES if t.has(c)):
        share = np.nan_to_num(t.num(col))
        ax_share.barh(range(len(labels)), share, left=left, color=f"C{k}", label=name)
        left += share
    ax_share.set_yticks(range(len(labels)))
    ax_share.set_yticklabels(labels, fontsize=7)
    ax_share.invert_yaxis()
    ax_share.set_xlabel("share of the DEM's time [-]")
    ax_share.legend(fontsize=6, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncol=3)
    # What the dry rate over P's would be if only the integration pass took
    # time (pairs, lists, walls free): P's time a particle-step over the
    # integration's, both from the same run's rates and shares.
    ceiling = (t.num("dem_particle_steps_per_s") * t.num("dry_over_scene_p")
               / (t.num("dem_dry_particle_steps_per_s") * t.num("integration_share"))
               if t.has("integration_share") else None)
    for k, th in enumerate(sorted({float(x) for x in threads if math.isfinite(x)})):
        sel = np.flatnonzero(threads == th)
        o = sel[np.argsort(checkpoint[sel])]
        ax_rate.plot(checkpoint[o], t.num("dry_over_scene_p")[o], "o-", color=f"C{k}", ms=4, lw=1,
                     label=f"{th:g} thread{'s' if th != 1 else ''}")
        if ceiling is not None:
            ax_rate.plot(checkpoint[o], ceiling[o], ".:", color=f"C{k}", lw=1.2, ms=4,
                         label=f"integration alone, {th:g} thr")
        if t.has("ceiling_over_scene_p"):
            ax_rate.plot(checkpoint[o], t.num("ceiling_over_scene_p")[o], "x-.", color=f"C{k}", lw=1.2, ms=4,
                         label=f"+ contacts at B's cost, {th:g} thr")
        # Coloured as the phase's bars; solid one thread, dashed more.
        for col, colour, marker, name in (("integration_over_floor", "C0", "o", "integration"),
                                          ("drag_over_floor", "C5", "s", "drag"),
                                          ("pairs_unit_over_scene_b", "C2", "^", "pairs a unit / B's")):
            if t.has(col):
                ax_floor.plot(checkpoint[o], t.num(col)[o], marker + ("-" if th == 1 else "--"), color=colour, ms=4,
                              lw=1, label=f"{name}, {th:g} thr")
    ax_rate.axhline(PLUME_DRY_OVER_P_GOAL, color="tab:red", ls="--", lw=1.2, label="goal (issue 19, 2a)")
    ax_rate.set_ylim(0.0, max(1.0, float(np.nanmax(t.num("dry_over_scene_p"))) * 1.1,
                              float(np.nanmax(ceiling)) * 1.1 if ceiling is not None else 0.0))
    ax_rate.set_xlabel("checkpoint time [s]")
    ax_rate.set_ylabel("dry DEM rate / scene P's rate [-]")
    ax_floor.axhline(1.0, color="grey", lw=0.8)
    ax_floor.set_xlabel("checkpoint time [s]")
    ax_floor.set_ylabel("phase time / its reference [-]")
    for ax in (ax_share, ax_rate, ax_floor):
        ax.grid(alpha=0.3)
    ax_rate.legend(fontsize=7)
    if ax_floor.lines[1:]:
        ax_floor.legend(fontsize=6)
    fig.suptitle(title)
    dates = sorted({str(r["date"]) for r in t.rows if r.get("date")})
    note = ("Dry: the DEM without its drag; scene P: the same 28224 grains falling as a block without contacts "
            "or fluid, timed in the same run. Integration alone (dotted): the dry rate over P's if the pairs, "
            "lists and walls took no time, a ceiling no pair pass can reach. Plus contacts (dash-dot): the same "
            "with the touching pairs at scene B's cost a contact (3.5 units of B's time a unit of pair work), "
            "the pair tests, near-set filterings and list builds still free. "
            "Floor: a pass that only loads and stores the phase's arrays "
            "(benchmarks/dem/streaming_floor.hpp) on as many grains and threads. Pairs a unit: the pair phase's "
            "time a pair tested (a touching pair counting 3.5) over the same for scene B, the dense bed, timed in "
            "the same run"
            + (f". Measured {', '.join(dates)}" if dates else "") + ".")
    return Plot(title, fig, note)


def _plume_sweep(res: StudyResults | None) -> Plot:
    """Plume metrics at the end time against grain count, one line per mesh
    size, and the wall time of each run (benchmarks/sweeps/plume_sweep.cpp)."""
    title = "Plume metrics against grain count and mesh size (reduced plume, two-way)"
    if not (f := one_file(res, formats.pattern("benchmarks", "plume_sweep.csv"))):
        return missing("benchmarks", title, "plume_sweep.csv")
    t = f.table
    panels = [("front_depth_m", "front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
              ("radial_spread_m", "radial spread [mm]", 1e3)]
    panels += [(c, lab, k) for c, lab, k in (("dome_shape", "dome shape, least squares [-]", 1.0),
                                             ("peak_fluid_speed_mps", "peak fluid speed [m/s]", 1.0))
               if t.has(c)]
    panels.append(("wall_time_s", "wall time [s]", 1.0))
    fig, axes = grid(len(panels), 3, (3.8, 3.0))
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
    if not (f := one_file(res, formats.pattern("benchmarks", "scaling.csv"))):
        return missing("benchmarks", title, "scaling.csv")
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
    log_log(ax_cost, "problem size N (particles or tetrahedra)", "time per step / N [ns]")
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
    if not (cost := one_file(res, pat_cost)):
        plots.append(missing("benchmarks", title, "accuracy_cost.csv"))
    else:
        t = cost.table
        sweeps = list(dict.fromkeys(str(r["sweep"]) for r in t.rows))
        fig, axes = grid(len(sweeps), 3, (3.8, 3.4))
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
        plots.append(titled(fig, title, "; ".join(remarks)))
    title = "Benchmark trends against commit"
    if not (hist := one_file(res, pat_hist)):
        plots.append(missing("benchmarks", title, "history.csv (or --history)"))
        return plots
    t = hist.table
    commits = list(dict.fromkeys(str(r["commit"]) for r in t.rows))
    names = list(dict.fromkeys(str(r["benchmark"]) for r in t.rows))
    # The benchmarks with the longest history first (a trend needs points),
    # then in the history's order.
    history_length = {n: len({str(r["commit"]) for r in t.rows if r["benchmark"] == n}) for n in names}
    shown = sorted(names, key=lambda n: -history_length[n])[:12]
    fig, axes = grid(len(shown), 3, (3.8, 2.8))
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


plots = benchmarks

"""The fluidized bed's plots in the validation report (reports/fdem_report/plugins.py):
the pressure drop against the superficial velocity, rising and falling, with
Ergun's packed branch and the buoyant weight per area; the bed height against
the velocity with Richardson-Zaki's expansion; and what accuracy costs (the
sweep's errors against CPU time, Pareto front marked). Reads stages.csv
(fluidized_bed_check.cpp) and accuracy_cost.csv (fluidized_bed_sweep.cpp);
every reference curve is drawn from the numbers the check wrote beside the
stages (Ergun's a U + b U^2 at the settled bed, U_t and n of Richardson-Zaki)."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column, Schema
from fdem_report.figures import Plot, missing, one_file, pareto_front

TITLE = "Fluidized bed (dense regime)"
STAGES = Schema("fluidized-bed stages: pressure drop, bed height and momentum balance per stage", (
    Column("tier", "str"), Column("model", "str"), Column("stage"), Column("direction", "str"),
    Column("superficial_velocity_m_s"), Column("u_over_umf_ergun"), Column("pressure_drop_pa"),
    Column("pressure_drop_sd_pa"), Column("buoyant_weight_per_area_pa"), Column("bed_height_m"),
    Column("bed_porosity"), Column("drag_over_weight"), Column("grain_pressure_over_weight"),
    Column("fluid_pressure_over_weight"), Column("solid_pressure_over_weight"), Column("floor_load_over_weight"),
    Column("ergun_a_pa_s_per_m"), Column("ergun_b_pa_s2_per_m2"), Column("terminal_velocity_m_s"),
    Column("richardson_zaki_n"), Column("solid_height_m")))
COST = Schema("fluidized-bed accuracy-cost sweep", (
    Column("sweep", "str"), Column("setting", "str"), Column("plateau_error"), Column("umf_error"),
    Column("packed_error"), Column("wall_time_s"), Column("cpu_time_s")))
PATTERNS = [(r"stages\.csv", STAGES, "stages.csv"), (r"accuracy_cost\.csv", COST, "accuracy_cost.csv")]

MARKERS = {"rising": "^", "falling": "v"}


def _groups(t):
    """(tier, model) pairs in file order."""
    return list(dict.fromkeys((str(r["tier"]), str(r["model"])) for r in t.rows))


def _drop_and_height(t):
    fig = Figure(figsize=(11.0, 4.2), layout="constrained")
    ax_dp, ax_h = fig.subplots(1, 2)
    u_all = t.num("superficial_velocity_m_s")
    for g, (tier, model) in enumerate(_groups(t)):
        idx = [i for i, r in enumerate(t.rows) if (str(r["tier"]), str(r["model"])) == (tier, model)]
        colour = f"C{g}"
        weight = float(t.num("buoyant_weight_per_area_pa")[idx[0]])
        a, b = float(t.num("ergun_a_pa_s_per_m")[idx[0]]), float(t.num("ergun_b_pa_s2_per_m2")[idx[0]])
        u = np.linspace(0.0, 1.05 * float(np.nanmax(u_all[idx])), 200)
        ergun = a * u + b * u * u
        ax_dp.plot(u * 1e3, np.minimum(ergun, weight), "--", color=colour, lw=0.9,
                   label=f"Ergun (settled bed) capped at W/A ({tier})" if model == "vans_a" else None)
        ax_dp.axhline(weight, color="k", lw=0.6, ls=":")
        for direction in ("rising", "falling"):
            sel = [i for i in idx if str(t.rows[i]["direction"]) == direction]
            if not sel:
                continue
            ax_dp.plot(u_all[sel] * 1e3, t.num("pressure_drop_pa")[sel], MARKERS[direction] + "-", color=colour, ms=5,
                       lw=0.8, label=f"{model} {direction} ({tier})")
            if model != "simplified":  # its bed does not lift
                ax_h.plot(u_all[sel] * 1e3, t.num("bed_height_m")[sel] * 1e3, MARKERS[direction] + "-", color=colour,
                          ms=5, lw=0.8, label=f"{model} {direction} ({tier})")
        if model != "simplified":
            ut, n, hs = (float(t.num(c)[idx[0]]) for c in ("terminal_velocity_m_s", "richardson_zaki_n", "solid_height_m"))
            fluidized = [i for i in idx if float(t.num("u_over_umf_ergun")[i]) >= 1.0]
            if fluidized:
                uf = np.linspace(0.8 * float(np.nanmin(u_all[fluidized])), 1.05 * float(np.nanmax(u_all[fluidized])), 100)
                ax_h.plot(uf * 1e3, hs / (1.0 - (uf / ut) ** (1.0 / n)) * 1e3, "--", color=colour, lw=0.9,
                          label=f"Richardson-Zaki, n = {n:.2f} ({tier})")
    ax_dp.set_xlabel("superficial velocity U [mm/s]")
    ax_dp.set_ylabel("pressure drop [Pa]")
    ax_dp.set_title("pressure drop (dotted: buoyant weight per area W/A)", fontsize=9)
    ax_h.set_xlabel("superficial velocity U [mm/s]")
    ax_h.set_ylabel("bed height H = 2 <z> [mm]")
    ax_h.set_title("bed height against Richardson-Zaki", fontsize=9)
    for ax in (ax_dp, ax_h):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
    fig.suptitle("Fluidized bed: pressure drop and bed height against superficial velocity")
    return Plot("Fluidized bed: pressure drop and bed height against superficial velocity", fig,
                "the plateau lies 5-8 % below W/A and the packed branch 13 % below Ergun at the shape-function "
                "porosity (known deviations, reference_data/fluidized_bed.csv and the study README)")


def _cost(t):
    title = "Fluidized bed: what accuracy costs (error against CPU time, Pareto front marked)"
    sweeps = list(dict.fromkeys(str(r["sweep"]) for r in t.rows))
    fig = Figure(figsize=(3.6 * len(sweeps), 3.6), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, len(sweeps)))
    for ax, sweep in zip(axes, sweeps):
        idx = np.array([i for i, r in enumerate(t.rows) if r["sweep"] == sweep])
        cpu = t.num("cpu_time_s")[idx]
        for column, colour, label in (("plateau_error", "tab:blue", "plateau |dp/(W/A) - 1|"),
                                      ("umf_error", "tab:orange", "onset |U_mf/Ergun - 1|")):
            err = t.num(column)[idx]
            ax.plot(cpu, err, "o", color=colour, ms=5, label=label)
            for i, k in enumerate(idx):
                ax.annotate(str(t.rows[k]["setting"]), (cpu[i], err[i]), fontsize=6, xytext=(3, 3),
                            textcoords="offset points")
            front = pareto_front(cpu, err)
            if len(front):
                ax.step(cpu[front], err[front], "-", where="post", color=colour, lw=1.0)
        ax.set_yscale("log")
        ax.set_xlabel("CPU time, one thread [s]")
        ax.set_ylabel("error [-]")
        ax.set_title(f"sweep: {sweep}", fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=6)
    fig.suptitle(title)
    return Plot(title, fig, "model A on the fast bed (400 grains), one setting changed at a time from cell/d 2, "
                            "shape-function porosity, fluid step 2.5e-3 s, semi-implicit exchange; CPU time of the "
                            "whole run (dry settle and five stages); nan errors are runs that failed")


def plots(res):
    if res is None:  # the study did not run: its section says so, no empty figure
        return []
    stages, cost = one_file(res, PATTERNS[0][0]), one_file(res, PATTERNS[1][0])
    return [_drop_and_height(stages.table) if stages else
            missing("fluidized_bed", "Fluidized bed: pressure drop and bed height against superficial velocity",
                    "stages.csv"),
            _cost(cost.table) if cost else
            missing("fluidized_bed", "Fluidized bed: what accuracy costs", "accuracy_cost.csv (nightly sweep)")]

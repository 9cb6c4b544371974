"""The DEM verification's plots in the validation report (reports/fdem_report/plugins.py):
restitution and contact time against damping ratio, energy error against the DEM step.
Reads restitution.csv and energy.csv."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, WIDE, fitted_order, log_log, missing, one_file, titled
from fdem_report.inputs import StudyResults

S = "str"

TITLE = "DEM: collisions and energy"
DEM_RESTITUTION = Schema("restitution against damping ratio", (
    C("case", S), C("zeta"), C("e_analytic"), C("e_measured")),
    optional=(C("tc_analytic_s"), C("tc_measured_s")))
DEM_ENERGY = Schema("energy error against DEM step", (C("dt_s"), C("energy_error_rel")),
                    optional=(C("case", S),))

PATTERNS = [(r"restitution\.csv", DEM_RESTITUTION, "restitution.csv"), (r"energy\.csv", DEM_ENERGY, "energy.csv")]


def dem(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_rest, pat_energy = (p for p, _, _ in PATTERNS)
    title = "Restitution and contact time against damping ratio"
    if not (rest := one_file(res, pat_rest)):
        plots.append(missing("dem", title, "restitution.csv"))
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
        plots.append(titled(fig, title))
    title = "Energy error against DEM step (no damping, no friction)"
    if not (energy := one_file(res, pat_energy)):
        plots.append(missing("dem", title, "energy.csv"))
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
        log_log(ax, "DEM step dt [s]", "|relative energy error| [-]")
        plots.append(titled(fig, title))
    return plots


plots = dem

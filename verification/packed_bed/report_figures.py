"""The packed bed's plots in the validation report (reports/fdem_report/plugins.py):
-dp/dz over Ergun against the particle Reynolds number, one line per fluid
model, with the 5 % band of reference_data/packed_bed.csv; and -dp/dz itself
beside Ergun's law. Reads gradient.csv (packed_bed_check.cpp)."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column, Schema
from fdem_report.figures import Plot, missing, one_file

TITLE = "Packed bed: pressure gradient against Ergun (VANS models)"
GRADIENT = Schema("pressure gradient against Ergun per model and Reynolds number", (
    Column("tier", "str"), Column("re_p"), Column("superficial_velocity_m_s"), Column("porosity"),
    Column("model", "str"), Column("gradient_pa_m"), Column("ergun_pa_m"), Column("ratio"),
    Column("interstitial_over_u_eps")))
PATTERNS = [(r"gradient\.csv", GRADIENT, "gradient.csv")]


def plots(res):
    title = "-dp/dz over Ergun against Re_p, and -dp/dz beside Ergun's law"
    if not (gradient := one_file(res, PATTERNS[0][0])):
        return [missing("packed_bed", title, "gradient.csv")]
    t = gradient.table
    fig = Figure(figsize=(11.0, 4.0), layout="constrained")
    ax_ratio, ax_grad = fig.subplots(1, 2)
    models = list(dict.fromkeys(str(r["model"]) for r in t.rows))
    tiers = list(dict.fromkeys(str(r["tier"]) for r in t.rows))
    re_all = t.num("re_p")
    for model in models:
        for tier in tiers:
            idx = [i for i, r in enumerate(t.rows) if r["model"] == model and r["tier"] == tier]
            if not idx:
                continue
            o = np.argsort(re_all[idx])
            sel = np.array(idx)[o]
            label = f"{model} ({tier})"
            ax_ratio.plot(re_all[sel], t.num("ratio")[sel], "o-", ms=4, lw=1, label=label)
            ax_grad.plot(re_all[sel], t.num("gradient_pa_m")[sel], "o", ms=4, label=label)
    o = np.argsort(re_all)
    ax_grad.plot(re_all[o], t.num("ergun_pa_m")[o], "k-", lw=1, label="Ergun 1952 (Eq. 1)")
    ax_ratio.axhspan(0.95, 1.05, color="tab:green", alpha=0.1, lw=0, label="Ergun +- 5 % (gate)")
    ax_ratio.axhline(1.0, color="k", lw=0.8)
    for ax in (ax_ratio, ax_grad):
        ax.set_xscale("log")
        ax.set_xlabel("Re_p = rho U d / mu [-]")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    ax_grad.set_yscale("log")
    ax_ratio.set_ylabel("-dp/dz / Ergun [-]")
    ax_grad.set_ylabel("-dp/dz [Pa/m]")
    fig.suptitle(title)
    return [Plot(title, fig, "the simplified model (Eq. 21-22) is not Ergun by construction: its own closed form "
                             "is its reference row (reference_data/packed_bed.csv)")]

"""Hindered settling's plot in the validation report (reports/fdem_report/plugins.py):
the mean settling velocity over the single grain's terminal velocity against
the porosity, one colour per single-grain Reynolds number, each fluid model
with its own marker, beside Richardson-Zaki's eps^n with Garside &
Al-Dibouni's n for that Re_t (n recovered from the check's own eps^n column,
so no reference number is typed here). Reads settling.csv
(hindered_settling_check.cpp)."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column, Schema
from fdem_report.figures import Plot, missing, one_file

TITLE = "Hindered settling (dense regime)"
SETTLING = Schema("hindered settling: mean velocity over terminal per solid fraction and Reynolds number", (
    Column("tier", "str"), Column("model", "str"), Column("solid_fraction"), Column("reynolds_t"),
    Column("viscosity_pa_s"), Column("terminal_velocity_m_s"), Column("grains"), Column("settling_velocity_m_s"),
    Column("velocity_over_terminal"), Column("richardson_zaki_ga"), Column("richardson_zaki_1954"),
    Column("closed_form_over_terminal"), Column("volume_flux_closure")))
PATTERNS = [(r"settling\.csv", SETTLING, "settling.csv")]
MARKERS = {"vans_a": "o", "simplified": "s"}


def plots(res):
    if res is None:  # the study did not run: its section says so, no empty figure
        return []
    title = "Hindered settling: v / U_t against porosity, beside Richardson-Zaki"
    if not (settling := one_file(res, PATTERNS[0][0])):
        return [missing("hindered_settling", title, "settling.csv")]
    t = settling.table
    fig = Figure(figsize=(7.5, 4.8), layout="constrained")
    ax = fig.subplots()
    eps_all = 1.0 - t.num("solid_fraction")
    re_all = t.num("reynolds_t")
    re_values = sorted({round(float(r), 6) for r in re_all if np.isfinite(r)})
    eps_line = np.linspace(0.65, 1.0, 100)
    for c, re in enumerate(re_values):
        idx = [i for i in range(len(t.rows)) if abs(float(re_all[i]) - re) <= 1e-6 * re]
        colour = f"C{c}"
        # n of Garside & Al-Dibouni for this Re_t, from the check's eps^n column.
        ns = [np.log(float(t.num("richardson_zaki_ga")[i])) / np.log(float(eps_all[i])) for i in idx
              if float(eps_all[i]) < 1.0]
        if ns:
            n = float(np.median(ns))
            ax.plot(eps_line, eps_line ** n, "-", color=colour, lw=0.9, label=f"Richardson-Zaki, Re_t {re:g} (n {n:.2f})")
        for model, marker in MARKERS.items():
            sel = [i for i in idx if str(t.rows[i]["model"]) == model]
            if sel:
                ax.plot(eps_all[sel], t.num("velocity_over_terminal")[sel], marker, color=colour, ms=6,
                        mfc="none" if model == "simplified" else colour, label=f"{model}, Re_t {re:g}")
    ax.set_xlabel("porosity eps = 1 - phi [-]")
    ax.set_ylabel("v / U_t [-]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    fig.suptitle(title)
    return [Plot(title, fig, "filled: model A (volume-averaged, gated at 10 % of Richardson-Zaki); open: the "
                             "simplified model, which has no backflow (tabulated beside it)")]

"""The fluid solver's plot in the validation report (reports/fdem_report/plugins.py): error
against mesh size with fitted orders. Reads convergence.csv."""
import math

import numpy as np

from fdem_report import formats
from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, fitted_order, grid, missing, one_file, positive
from fdem_report.inputs import StudyResults

S = "str"

TITLE = "Fluid solver: convergence and exact solutions"
FLUID_CONVERGENCE = Schema("error against mesh size", (
    C("case", S), C("quantity", S), C("h_m"), C("error")), optional=(C("expected_order"),))

PATTERNS = [(r"convergence\.csv", FLUID_CONVERGENCE, "convergence.csv")]


def fluid(res: StudyResults | None) -> list[Plot]:
    title = "Convergence under mesh refinement"
    if not (conv := one_file(res, formats.pattern("fluid", "convergence.csv"))):
        return [missing("fluid", title, "convergence.csv")]
    t = conv.table
    cases = sorted({str(r["case"]) for r in t.rows})
    fig, axes = grid(len(cases), 3, (3.8, 3.4))
    h, err = t.num("h_m"), t.num("error")
    expected = t.num("expected_order") if t.has("expected_order") else np.full(len(h), np.nan)
    for ax, case in zip(axes, cases):
        for q in sorted({str(r["quantity"]) for r in t.rows if r["case"] == case}):
            sel = np.array([r["case"] == case and r["quantity"] == q for r in t.rows])
            o = np.argsort(h[sel])
            p = fitted_order(h[sel], err[sel])
            hs, es = positive(h[sel][o], err[sel][o])
            # The finest pair's order too: the table's order rows name a mesh pair (e.g. 8 -> 12
            # cells), which differs from the fit over all h when the error is not yet asymptotic.
            p2 = math.log(es[1] / es[0]) / math.log(hs[1] / hs[0]) if len(hs) >= 2 and hs[1] != hs[0] else None
            label = q if p is None else (f"{q}: order {p:.2f} (fit, all h)"
                                         + (f", {p2:.2f} (finest pair)" if p2 is not None and len(hs) > 2 else ""))
            line, = ax.plot(h[sel][o], err[sel][o], "o-", ms=4, label=label)
            exp_q = expected[sel][np.isfinite(expected[sel])]
            hx, ey = positive(h[sel][o], err[sel][o])
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


plots = fluid

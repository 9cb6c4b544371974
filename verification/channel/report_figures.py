"""The channel study's plot in the validation report (reports/fdem_report/plugins.py): the
outlet velocity profiles with the fitted near-bed slopes (paper Table 3). Reads
profile_<case>.csv and slopes.csv (channel_check.cpp)."""
import math

import numpy as np
from matplotlib.figure import Figure

from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, missing
from fdem_report.inputs import StudyResults

S = "str"

TITLE = "Channel flow over a bed (Sect. 4.3, Table 3)"
CHANNEL_PROFILE = Schema("outlet velocity profile", (C("z_m"), C("u_mps")))
CHANNEL_SLOPES = Schema("fitted near-bed slopes", (
    C("case", S), C("slope_deg"), C("dudz_1ps"), C("z_from_m"), C("z_to_m"), C("u_at_z_from_mps")),
    optional=(C("slope_paper_deg"), C("bed_top_m")))

PATTERNS = [
    (r"profile_(?P<case>wall|bed)\.csv", CHANNEL_PROFILE, "profile_<case>.csv"),
    (r"slopes\.csv", CHANNEL_SLOPES, "slopes.csv"),
]


def channel(res: StudyResults | None) -> list[Plot]:
    title = "Outlet velocity profiles with the fitted near-bed slopes"
    pat_prof, pat_slopes = (p for p, _, _ in PATTERNS)
    profiles = {s.keys["case"]: s for s in res.files(pat_prof)} if res else {}
    if not profiles:
        return [missing("channel", title, "profile_wall.csv / profile_bed.csv")]
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


plots = channel

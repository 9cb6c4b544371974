"""The plume's plots in the validation report (reports/fdem_report/plugins.py): dome metrics
against time and snapshots of the grains and the mid-plane fluid speed (paper Sect. 4.4); and
the main job's plume (plume_main.yaml) beside the full one, a second report section
(SECTIONS). Reads metrics_<mode>.csv, particles_<mode>_t<T>s.csv, fluid_speed_<mode>_t<T>s.csv."""
import numpy as np
from matplotlib.figure import Figure

from fdem_report import formats
from fdem_report.csvio import Column as C, Schema
from fdem_report.figures import Plot, grid, key_float, missing, titled
from fdem_report.inputs import SeriesFile, StudyResults

S = "str"

TITLE = "Salt plume (Sect. 4.4, Table 4)"
PLUME_METRICS = Schema("dome metrics against time", (
    C("t_s"), C("front_depth_m"), C("centroid_depth_m"), C("radial_spread_m")),
    optional=(C("dome_shape"), C("peak_fluid_speed_mps")))
PLUME_PARTICLES = Schema("grain positions at one time", (C("x_m"), C("y_m"), C("z_m"), C("d_m")))
PLUME_FLUID = Schema("fluid speed on the mid-plane y = W/2", (C("x_m"), C("z_m"), C("speed_mps")))

PATTERNS = [
    (r"metrics_(?P<mode>twoway|oneway_f2p|oneway_p2f)\.csv", PLUME_METRICS, "metrics_<mode>.csv"),
    (r"particles_(?P<mode>twoway|oneway_f2p|oneway_p2f)_t(?P<t_s>[0-9]+(?:\.[0-9]+)?)s\.csv",
     PLUME_PARTICLES, "particles_<mode>_t<T>s.csv"),
    (r"fluid_speed_(?P<mode>twoway|oneway_f2p|oneway_p2f)_t(?P<t_s>[0-9]+(?:\.[0-9]+)?)s\.csv",
     PLUME_FLUID, "fluid_speed_<mode>_t<T>s.csv"),
]

PLUME_MODES = {"twoway": "two-way", "oneway_f2p": "one-way fluid to particle",
               "oneway_p2f": "one-way particle to fluid"}

# The main job's plume (verification/plume/plume_main.yaml): its metrics only, its own section.
MAIN_PATTERNS = [
    (r"metrics_(?P<mode>twoway|oneway_f2p|oneway_p2f)\.csv", PLUME_METRICS, "metrics_<mode>.csv"),
]


def plume(res: StudyResults | None) -> list[Plot]:
    plots = []
    pat_metrics, pat_particles, pat_fluid = (p for p, _, _ in PATTERNS)
    title = "Dome metrics against time, two-way and one-way"
    metrics = res.files(pat_metrics) if res else []
    if not metrics:
        plots.append(missing("plume", title, "metrics_<mode>.csv"))
    else:
        cols = [("front_depth_m", "cloud front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
                ("radial_spread_m", "radial spread (2nd moment) [mm]", 1e3), ("dome_shape", "dome shape, least squares [-]", 1.0),
                ("peak_fluid_speed_mps", "peak fluid speed [mm/s]", 1e3)]
        cols = [c for c in cols if any(m.table.has(c[0]) for m in metrics)]
        fig, axes = grid(len(cols), 3, (3.7, 3.0))
        styles = {"twoway": ("tab:red", "-"), "oneway_f2p": ("tab:blue", "--"), "oneway_p2f": ("tab:green", ":")}
        for ax, (c, label, scale) in zip(axes, cols):
            for m in sorted(metrics, key=lambda s: list(PLUME_MODES).index(s.keys["mode"])):
                if m.table.has(c):
                    colour, ls = styles[m.keys["mode"]]
                    ax.plot(m.table.num("t_s"), m.table.num(c) * scale, ls, color=colour, lw=1.4,
                            label=PLUME_MODES[m.keys["mode"]])
            ax.set_xlabel("t [s]")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        plots.append(titled(fig, title))
    for pattern, what, draw, tpl in ((pat_particles, "grains, side view (x-z)", _plume_particles,
                                      "particles_<mode>_t<T>s.csv"),
                                     (pat_fluid, "fluid speed on the mid-plane y = W/2", _plume_fluid,
                                      "fluid_speed_<mode>_t<T>s.csv")):
        files = res.files(pattern) if res else []
        if not files:
            plots.append(missing("plume", f"Snapshots: {what}", tpl))
            continue
        for mode in [m for m in PLUME_MODES if any(f.keys["mode"] == m for f in files)]:
            snaps = sorted((f for f in files if f.keys["mode"] == mode), key=lambda f: key_float(f, "t_s"))[:6]
            title = f"Snapshots: {what}, {PLUME_MODES[mode]}"
            plots.append(Plot(title, draw(snaps, title)))
    return plots


def plume_main(res: StudyResults | None) -> list[Plot]:
    """The main job's plume beside the full one: the same metrics against time,
    the full run's (results folder plume/, tier full) dashed where it exists."""
    pat_metrics = formats.pattern("plume_main", "metrics_<mode>.csv")
    title = "Main-job plume (contacts off, 10 subcycles) against the full plume"
    metrics = res.files(pat_metrics) if res else []
    if not metrics:
        return [missing("plume_main", title, "metrics_<mode>.csv")]
    full = []
    sibling = res.folder.parent / "plume"
    if (sibling / "meta.json").is_file():
        from fdem_report.inputs import load_study
        other = load_study(sibling, "plume")
        if other.meta and other.meta.get("tier") == "full":
            full = other.files(formats.pattern("plume", "metrics_<mode>.csv"))
    cols = [("front_depth_m", "cloud front depth [mm]", 1e3), ("centroid_depth_m", "centroid depth [mm]", 1e3),
            ("radial_spread_m", "radial spread (2nd moment) [mm]", 1e3), ("dome_shape", "dome shape, least squares [-]", 1.0),
            ("peak_fluid_speed_mps", "peak fluid speed [mm/s]", 1e3)]
    cols = [c for c in cols if any(m.table.has(c[0]) for m in metrics)]
    fig, axes = grid(len(cols), 3, (3.7, 3.0))
    colours = {"twoway": "tab:red", "oneway_f2p": "tab:blue", "oneway_p2f": "tab:green"}
    for ax, (c, label, scale) in zip(axes, cols):
        for runs, ls, lw, who in ((metrics, "-", 1.4, "main"), (full, "--", 1.0, "full")):
            for m in runs:
                if m.table.has(c) and m.keys["mode"] != "oneway_p2f":
                    ax.plot(m.table.num("t_s"), m.table.num(c) * scale, ls, color=colours[m.keys["mode"]], lw=lw,
                            label=f"{PLUME_MODES[m.keys['mode']]}, {who}")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6)
    fig.suptitle(title + ("" if full else " (no full run in these results: main only)"))
    return [Plot(title, fig)]


def _plume_particles(snaps: list[SeriesFile], title: str) -> Figure:
    fig, axes = grid(len(snaps), 6, (1.9, 4.2))
    xs = np.concatenate([s.table.num("x_m") for s in snaps]) * 1e3
    zs = np.concatenate([s.table.num("z_m") for s in snaps]) * 1e3
    for ax, s in zip(axes, snaps):
        d = s.table.num("d_m")
        size = 2.0 * (d / np.nanmean(d)) ** 2 if len(d) else 1.0
        ax.scatter(s.table.num("x_m") * 1e3, s.table.num("z_m") * 1e3, s=size, c="saddlebrown",
                   linewidths=0, alpha=0.6, rasterized=True)
        ax.set_title(f"t = {key_float(s, 't_s'):g} s ({len(d)} grains)", fontsize=8)
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
    from fdem_report.csvio import InputError
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
    fig, axes = grid(len(snaps), 6, (1.9, 4.2))
    mesh = None
    for ax, s, (ux, uz, g) in zip(axes, snaps, grids):
        mesh = ax.pcolormesh(ux * 1e3, uz * 1e3, g * 1e3, shading="nearest", vmin=0, vmax=vmax, cmap="viridis")
        ax.set_title(f"t = {key_float(s, 't_s'):g} s", fontsize=8)
        ax.set_xlabel("x [mm]")
        ax.set_aspect("equal")
    axes[0].set_ylabel("z [mm]")
    if mesh is not None:
        fig.colorbar(mesh, ax=list(axes), label="|u| [mm/s]", shrink=0.8)
    fig.suptitle(title)
    return fig


def check(res: StudyResults) -> None:
    """The mid-plane files must be full grids; checked before anything is drawn."""
    for f in res.files(formats.pattern("plume", "fluid_speed_<mode>_t<T>s.csv")):
        grid_from_long(f)


plots = plume
SECTIONS = {"plume_main": dict(title="Salt plume, main job (contacts off) against the full plume", patterns=MAIN_PATTERNS, plots=plume_main)}

"""Every file the report reads, with its header contract. reports/FORMATS.md is
the human-readable copy of this module; tests/test_formats_doc.py keeps the two
in step. Files live in $RESULTS/<study>/ unless noted."""
from __future__ import annotations

from .csvio import Column as C, Schema

N = "num"
S = "str"

# reference_data/<study>.csv (format owned by reference_data/README.md)
REFERENCE = Schema("reference rows", tuple(C(n, S) for n in (
    "id", "quantity", "unit", "value", "tolerance", "tolerance_kind", "gate", "source", "provenance")),
    optional=(C("class", S), C("u_ref", S)), exact_order=True)
# $RESULTS/<study>/values.csv
VALUES = Schema("our values", (C("id", S), C("value", S)), exact_order=True)

# ---- settling --------------------------------------------------------------
SETTLING_SERIES = Schema("settling v(t) for one diameter", (
    C("t_s"), C("v_oneway_mps"), C("v_twoway_mps"), C("v_gsl_mps")))
SETTLING_TERMINAL = Schema("terminal velocity against diameter", (
    C("d_m"), C("vt_exp_mps"), C("vt_paper_mps"), C("vt_stokes_mps"), C("vt_gsl_mps"),
    C("vt_oneway_mps"), C("vt_twoway_mps")), optional=(C("u_num_twoway_mps"),),
    extra_pattern=r"vt_[a-z0-9_.+-]+_mps")

# ---- mesh sensitivity -------------------------------------------------------
MESH_SERIES = Schema("porosity and velocity against time", (C("t_s"), C("porosity"), C("v_mps")))
MESH_AMPLITUDES = Schema("oscillation amplitudes against ratio", (
    C("ratio"), C("start", S), C("scheme", S), C("porosity_amp_pct"), C("velocity_amp_pct")),
    optional=(C("vt_mps"), C("wall_time_s"), C("porosity_amp_paper_pct"),
              C("velocity_amp_paper_pct"), C("porosity_amp_closed_form_pct")))

# ---- channel ----------------------------------------------------------------
CHANNEL_PROFILE = Schema("outlet velocity profile", (C("z_m"), C("u_mps")))
CHANNEL_SLOPES = Schema("fitted near-bed slopes", (
    C("case", S), C("slope_deg"), C("dudz_1ps"), C("z_from_m"), C("z_to_m"), C("u_at_z_from_mps")),
    optional=(C("slope_paper_deg"), C("bed_top_m")))

# ---- plume ------------------------------------------------------------------
PLUME_METRICS = Schema("dome metrics against time", (
    C("t_s"), C("front_depth_m"), C("centroid_depth_m"), C("radial_spread_m")),
    optional=(C("dome_shape"), C("peak_fluid_speed_mps")))
PLUME_PARTICLES = Schema("grain positions at one time", (C("x_m"), C("y_m"), C("z_m"), C("d_m")))
PLUME_FLUID = Schema("fluid speed on the mid-plane y = W/2", (C("x_m"), C("z_m"), C("speed_mps")))

# ---- fluid solver level -----------------------------------------------------
FLUID_CONVERGENCE = Schema("error against mesh size", (
    C("case", S), C("quantity", S), C("h_m"), C("error")), optional=(C("expected_order"),))

# ---- DEM verification -------------------------------------------------------
DEM_RESTITUTION = Schema("restitution against damping ratio", (
    C("case", S), C("zeta"), C("e_analytic"), C("e_measured")),
    optional=(C("tc_analytic_s"), C("tc_measured_s")))
DEM_ENERGY = Schema("energy error against DEM step", (C("dt_s"), C("energy_error_rel")),
                    optional=(C("case", S),))

# ---- benchmarks -------------------------------------------------------------
ACCURACY_COST = Schema("accuracy-cost sweep", (
    C("sweep", S), C("setting", S), C("error"), C("wall_time_s")), optional=(C("error_kind", S),))
HISTORY = Schema("benchmark history", (
    C("commit", S), C("date", S), C("benchmark", S), C("value"), C("unit", S)),
    optional=(C("compiler", S), C("machine", S), C("regression"), C("noise_band_rel")))

PLUME_SWEEP = Schema("plume metrics against grain count and mesh size", (
    C("mode", S), C("grains"), C("d_m"), C("cell_m"), C("t_s"), C("front_depth_m"), C("centroid_depth_m"),
    C("radial_spread_m"), C("wall_time_s")),
    optional=(C("grains_fraction"), C("cell_nominal_mm"), C("cells", S), C("tets"), C("solid_fraction"),
              C("subcycles"), C("dem_step_s"), C("spread_growth_m"), C("dome_shape"), C("peak_fluid_speed_mps"),
              C("steps"), C("grains_lost"), C("setup_s"), C("fluid_s"), C("dem_s"), C("coupling_s"), C("threads")))
SCALING = Schema("cost against problem size", (
    C("case", S), C("size"), C("threads"), C("seconds_per_step")),
    optional=(C("unit", S), C("cpu_seconds_per_step"), C("load_average")))

# File name patterns (regular expressions on the base name) per study.
# Named groups are parsed from the name (numbers with '.' as decimal point).
PATTERNS: dict[str, list[tuple[str, Schema, str]]] = {
    "settling": [
        (r"series_d(?P<d_mm>[0-9]+(?:\.[0-9]+)?)mm\.csv", SETTLING_SERIES, "series_d<D>mm.csv"),
        (r"terminal\.csv", SETTLING_TERMINAL, "terminal.csv"),
    ],
    "mesh_sensitivity": [
        (r"series_r(?P<ratio>[0-9]+(?:\.[0-9]+)?)_(?P<start>centred|offset)_(?P<scheme>[a-z0-9]+)\.csv",
         MESH_SERIES, "series_r<ratio>_<start>_<scheme>.csv"),
        (r"amplitudes\.csv", MESH_AMPLITUDES, "amplitudes.csv"),
    ],
    "channel": [
        (r"profile_(?P<case>wall|bed)\.csv", CHANNEL_PROFILE, "profile_<case>.csv"),
        (r"slopes\.csv", CHANNEL_SLOPES, "slopes.csv"),
    ],
    "plume": [
        (r"metrics_(?P<mode>twoway|oneway_f2p|oneway_p2f)\.csv", PLUME_METRICS, "metrics_<mode>.csv"),
        (r"particles_(?P<mode>twoway|oneway_f2p|oneway_p2f)_t(?P<t_s>[0-9]+(?:\.[0-9]+)?)s\.csv",
         PLUME_PARTICLES, "particles_<mode>_t<T>s.csv"),
        (r"fluid_speed_(?P<mode>twoway|oneway_f2p|oneway_p2f)_t(?P<t_s>[0-9]+(?:\.[0-9]+)?)s\.csv",
         PLUME_FLUID, "fluid_speed_<mode>_t<T>s.csv"),
    ],
    # The main job's plume (verification/plume/plume_main.yaml): its metrics only.
    "plume_main": [
        (r"metrics_(?P<mode>twoway|oneway_f2p|oneway_p2f)\.csv", PLUME_METRICS, "metrics_<mode>.csv"),
    ],
    "fluid": [(r"convergence\.csv", FLUID_CONVERGENCE, "convergence.csv")],
    "dem": [
        (r"restitution\.csv", DEM_RESTITUTION, "restitution.csv"),
        (r"energy\.csv", DEM_ENERGY, "energy.csv"),
    ],
    "benchmarks": [
        (r"accuracy_cost\.csv", ACCURACY_COST, "accuracy_cost.csv"),
        (r"history\.csv", HISTORY, "history.csv"),
        (r"plume_sweep\.csv", PLUME_SWEEP, "plume_sweep.csv"),
        (r"scaling\.csv", SCALING, "scaling.csv"),
    ],
}


def pattern(study: str, template: str) -> str:
    """The file-name regex of a study's file, looked up by its template."""
    for regex, _, tpl in PATTERNS[study]:
        if tpl == template:
            return regex
    raise KeyError(f"{study}/{template}")


# Report order and titles; any other study (reference file or results folder)
# follows in alphabetical order with its table only.
STUDIES: dict[str, str] = {
    "settling": "Single-particle settling (Sect. 4.1, Table 1)",
    "mesh_sensitivity": "Mesh sensitivity (Sect. 4.2, Table 2)",
    "channel": "Channel flow over a bed (Sect. 4.3, Table 3)",
    "plume": "Salt plume (Sect. 4.4, Table 4)",
    "plume_main": "Salt plume, main job (contacts off) against the full plume",
    # Dense-regime studies: their own report_figures.py where they have one,
    # else their rows drawn against their tolerances (figures.rows_figure);
    # shown only when their reference rows or results exist.
    "packed_bed": "Packed bed: pressure gradient against Ergun (VANS models)",
    "vans_dilute": "VANS models in the dilute limit (against the simplified model)",
    "fluidized_bed": "Fluidized bed (dense regime)",
    "hindered_settling": "Hindered settling (dense regime)",
    "fluid": "Fluid solver: convergence and exact solutions",
    "dem": "DEM: collisions and energy",
    "hard_cases": "Hard cases: stability and refusals",
    "benchmarks": "What accuracy costs; benchmark trends",
}

PLUME_MODES = {"twoway": "two-way", "oneway_f2p": "one-way fluid to particle",
               "oneway_p2f": "one-way particle to fluid"}

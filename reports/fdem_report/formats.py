"""Every file the report reads, with its header contract: the shared ones here,
each study's own in its report_figures.py (plugins.py). reports/FORMATS.md is
the human-readable copy of them all; tests keep them
in step (tests/test_generator_unit.py, FormatsDocumented). Files live in $RESULTS/<study>/ unless noted."""
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
DEM_VS_LIGGGHTS = Schema("fdem's DEM against LIGGGHTS 3.8, side by side", (
    C("scene", S), C("threads"), C("fdem_particle_steps_per_s"), C("liggghts_particle_steps_per_s"), C("ratio")),
    optional=(C("fdem_spread"), C("liggghts_spread"), C("fdem_list_builds"), C("liggghts_list_builds"), C("reps"),
              C("date", S)))
PLUME_DEM_WORKLOAD = Schema("the plume's DEM from checkpoints against scene P", (
    C("checkpoint_s"), C("threads"), C("dem_particle_steps_per_s"), C("dem_dry_particle_steps_per_s"),
    C("dry_over_scene_p")),
    optional=(C("contacts"), C("entries_per_particle"), C("rebuilds_per_100_steps"), C("integration_share"),
              C("neighbour_build_share"), C("body_force_share"), C("pairs_share"), C("walls_share"),
              C("external_share"), C("integration_over_floor"), C("drag_over_floor"), C("pairs_ns_per_unit"),
              C("pairs_unit_over_scene_b"), C("ceiling_over_scene_p"), C("reps"), C("date", S)))
SCALING = Schema("cost against problem size", (
    C("case", S), C("size"), C("threads"), C("seconds_per_step")),
    optional=(C("unit", S), C("cpu_seconds_per_step"), C("load_average")))

# File name patterns (regular expressions on the base name) per study.
# Named groups are parsed from the name (numbers with '.' as decimal point).
# A study's own files are in its report_figures.py (plugins.register adds
# them here); the benchmarks' are here because the benchmark tools read them too.
PATTERNS: dict[str, list[tuple[str, Schema, str]]] = {
    "benchmarks": [
        (r"accuracy_cost\.csv", ACCURACY_COST, "accuracy_cost.csv"),
        (r"history\.csv", HISTORY, "history.csv"),
        (r"plume_sweep\.csv", PLUME_SWEEP, "plume_sweep.csv"),
        (r"scaling\.csv", SCALING, "scaling.csv"),
        (r"dem_vs_liggghts\.csv", DEM_VS_LIGGGHTS, "dem_vs_liggghts.csv"),
        (r"plume_dem_workload\.csv", PLUME_DEM_WORKLOAD, "plume_dem_workload.csv"),
    ],
}


def pattern(study: str, template: str) -> str:
    """The file-name regex of a study's file, looked up by its template."""
    for regex, _, tpl in PATTERNS[study]:
        if tpl == template:
            return regex
    raise KeyError(f"{study}/{template}")


# Report order; any other study (reference file or results folder) follows
# in alphabetical order.
ORDER: list[str] = ["settling", "mesh_sensitivity", "channel", "plume", "plume_main", "packed_bed", "vans_dilute",
                    "fluidized_bed", "hindered_settling", "fluid", "dem", "hard_cases", "benchmarks"]

# Section titles. A study with its own report_figures.py gives its TITLE there
# (plugins.register adds it here); these are the titles of the studies without
# one, whose rows are drawn against their tolerances (figures.rows_figure),
# shown only when their reference rows or results exist.
STUDIES: dict[str, str] = {
    "vans_dilute": "VANS models in the dilute limit (against the simplified model)",
    "fluidized_bed": "Fluidized bed (dense regime)",
    "hindered_settling": "Hindered settling (dense regime)",
    "hard_cases": "Hard cases: stability and refusals",
}

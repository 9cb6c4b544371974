#!/usr/bin/env python3
"""Weak-scaling model of fdem's DEM on P MPI ranks, built from the costs and
message sizes parallel_scaling.py measured on 1 and 2 ranks (its
parallel_scaling.json), for 1e7 and 1e8 grains on 64 and 1024 ranks.

The material is scene B's settled bed (4800 grains of 0.20-0.30 mm, the
densest anchor scene: the most contacts and ghosts per grain), scaled up to
a cube of N grains at B's number density. Per rank and DEM step:

  compute   T_c = c (n + g / 2)             n = N / P owned grains, g ghosts;
                                            c the measured 1-rank cost per
                                            grain-step; a ghost costs half a
                                            grain (its contacts with owned
                                            grains only)
  messages  T_m = m alpha + g b / beta      m messages of the ghost update
            + k 2 alpha log2 P              k allreduces (small: latency bound,
                                            recursive doubling)
            + G / beta                      G gathered bytes (below)
            + T_mesh                        the coupling's sums into the
                                            mesh (below)
  efficiency E = c n / (T_c + T_m)          against P ranks with no ghosts
                                            and no messages

Ghosts: slabs (fdem's decomposition, parallel/slab_partition.hpp) of a cube
of side L have two faces of L^2 each, g = 2 L^2 r_c rho, m = 2, and need a
slab at least r_c thick (parallel/grain_exchange.hpp refuses thinner);
3-D blocks (side a = L / P^(1/3), for comparison: LIGGGHTS' processor grid)
have g = rho ((a + 2 r_c)^3 - a^3), m = 6 (three staged swaps). r_c =
d_max + skin = 1.5 d_max (skin 0.5 d_max, the DEM engine's default).

b (bytes a ghost costs per step) is the 2-rank run's measured point-to-point
bytes per DEM step over its ghosts (counted from the grains of B_settled.csv
within r_c of the cut); when that run exchanged nothing (the grains
replicated), 48 bytes: a position and a velocity (6 doubles). k is the
measured allreduces per DEM step per rank. G: "before" (2026-12-03 13:00), every
rank gathered every grain after each fluid step for the probes, so each
rank received N records of R bytes every `subcycles` DEM steps, G = N R /
subcycles; "now" the probes are summed from each rank's own grains (two
allreduces of 8 and 3 doubles a fluid step) and the whole set is gathered
only for snapshots and checkpoints (not counted), G = 0.

The coupling's per-element sums (porosity's solid volume, the source
term's drag and solid: 5 doubles an element, twice a fluid step in two
messages), per DEM step, with a mesh of M = 5 N / (rho h^3) tetrahedra of
cells h = 3 d_max (the finest the centre porosity scheme allows, the most
elements: an upper bound):
  before   one MPI_Allreduce of the whole mesh's 5 M doubles a fluid step:
           T_mesh = 2 (5 M 8 bytes) / beta / subcycles (a ring allreduce
           sends and receives twice the array), whatever P is;
  now      neighbour records (parallel/element_sums.hpp): each rank sends
           (element, values) for the elements its grains touch that another
           rank needs, 7 doubles a record, 2 messages a fluid step to each
           neighbour. Slabs whose cut the fluid's rows follow: the elements
           within 3 (r_c + h) of each face (the ranks' contribution and read
           bands); the fluid's rows cut elsewhere (fdem today: by node index):
           at most every element the rank's grains touch, n / (grains an
           element); T_mesh = 4 alpha + E_sent 56 bytes / beta, over subcycles.

Network (assumed, not measured here): alpha = 2 us a message, beta = 1 GB/s
a rank (a 200 Gb/s InfiniBand link shared by 25-32 ranks of a node).
"""
import csv
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ANCHORS = (ROOT / ".." / "shared" / "anchors" / "liggghts").resolve()

ALPHA_S = 2e-6
BETA_B_PER_S = 1e9
GHOST_RECORD_BYTES = 48      # fallback: x, v as 6 doubles
GATHER_RECORD_BYTES = 96     # x, v, f, d, m and id as 12 eight-byte words
SUBCYCLES = 100              # DEM steps per fluid step (the plume's, Table 4)
CELL_OVER_D_MAX = 3.0        # mesh cell / largest diameter (the finest cells of the centre scheme)
MESH_FIELD_DOUBLES = 5       # porosity's solid (1), the source term's drag (3) and solid (1) per element
ELEMENT_RECORD_BYTES = 56    # 7 doubles: the element and its values, in the two messages of a fluid step


def bed_geometry():
    """Scene B's bed: grains, largest diameter, number density [1/m^3] and the
    grains within r_c of the 2-rank cut x = 6 mm (both sides)."""
    rows = list(csv.DictReader(open(ANCHORS / "gen" / "B_settled.csv")))
    d = [float(r["d"]) for r in rows]
    x = [float(r["x"]) for r in rows]
    z_top = max(float(r["z"]) + float(r["d"]) / 2 for r in rows)
    d_max = max(d)
    r_c = 1.5 * d_max
    volume = 0.012 * 0.0018 * z_top
    cut = 0.006
    ghosts = sum(1 for xi in x if abs(xi - cut) < r_c)
    return dict(grains=len(rows), d_max=d_max, r_c=r_c, density=len(rows) / volume, ghosts_at_cut=ghosts)


def model_rows(c_grain_s, ghost_bytes, allreduces, geometry):
    rows = []
    rho, r_c = geometry["density"], geometry["r_c"]
    for grains in (1e7, 1e8):
        side = (grains / rho) ** (1.0 / 3.0)
        for ranks in (64, 1024):
            n = grains / ranks
            ideal = c_grain_s * n
            for layout in ("slabs", "3-D blocks"):
                if layout == "slabs":
                    thickness = side / ranks
                    g = 2 * side * side * r_c * rho
                    messages = 2
                    feasible = thickness >= r_c
                else:
                    a = side / ranks ** (1.0 / 3.0)
                    thickness = a
                    g = rho * ((a + 2 * r_c) ** 3 - a ** 3)
                    messages = 6
                    feasible = a >= r_c
                reduce_s = allreduces * 2 * ALPHA_S * math.log2(ranks)
                # The coupling's mesh sums (docstring): the whole-mesh allreduce before, neighbour records now.
                h = CELL_OVER_D_MAX * geometry["d_max"]
                elements = 5 * grains / (rho * h ** 3)
                mesh_before = 2 * MESH_FIELD_DOUBLES * 8 * elements / BETA_B_PER_S / SUBCYCLES
                per_element = rho * h ** 3 / 5  # grains an element
                band = math.ceil(3 * (r_c + h) / h) * h  # thickness of the exchanged layer at a face
                faces = 2 if layout == "slabs" else 6
                face_area = side * side if layout == "slabs" else (side / ranks ** (1.0 / 3.0)) ** 2
                aligned = min(n / per_element, faces * face_area * band * 5 / h ** 3)
                misaligned = n / per_element
                mesh_now = (4 * ALPHA_S + misaligned * ELEMENT_RECORD_BYTES / BETA_B_PER_S) / SUBCYCLES
                t_c = c_grain_s * (n + g / 2)
                t_ghost = messages * ALPHA_S + g * ghost_bytes / BETA_B_PER_S
                gather = grains * GATHER_RECORD_BYTES / SUBCYCLES / BETA_B_PER_S
                before = t_c + t_ghost + reduce_s + gather + mesh_before
                now = t_c + t_ghost + reduce_s + mesh_now
                rows.append(dict(grains=grains, ranks=ranks, layout=layout, owned=n, ghosts=g,
                                 thickness_over_rc=thickness / r_c, feasible=feasible, compute_s=t_c,
                                 ghost_s=t_ghost, reduce_s=reduce_s, gather_s=gather, mesh_before_s=mesh_before,
                                 mesh_now_s=mesh_now, elements_sent_aligned=aligned, elements_sent=misaligned,
                                 elements=elements, efficiency_before=ideal / before, efficiency=ideal / now))
    return rows


def print_model(summary, grain_cost_s=None):
    """The model's table from parallel_scaling.json's summary; `grain_cost_s`
    replaces the measured cost per grain-step (e.g. a quiet machine's)."""
    geometry = bed_geometry()
    b = summary["cases"]["B"]
    measured_c = b["fdem_dem_1"] / (b["grains"] * b["steps"])
    c_grain = grain_cost_s if grain_cost_s else measured_c
    p2p = b["bytes_per_step"]["p2p"]
    measured_exchange = p2p > 0
    ghost_bytes = p2p / geometry["ghosts_at_cut"] if measured_exchange else GHOST_RECORD_BYTES
    allreduces = b["allreduces_per_step_per_rank"]
    print("Weak-scaling model (benchmarks/parallel/weak_scaling_model.py; assumptions in its docstring and "
          "benchmarks/README.md):")
    source = (f"given; measured {measured_c:.3g} s in the run" if grain_cost_s else
              f"scene B, 1 rank, {summary['date']}, load {summary['load_min']:.0f}-{summary['load_max']:.0f}: an upper bound")
    print(f"  c = {c_grain:.3g} s per grain-step ({source}), r_c = {geometry['r_c'] * 1e3:.3g} mm, "
          f"rho = {geometry['density']:.3g} grains/m^3")
    print(f"  b = {ghost_bytes:.3g} bytes per ghost per DEM step ("
          + (f"measured: {p2p:.3g} B/step over {geometry['ghosts_at_cut']} grains within r_c of the cut"
             if measured_exchange else "no exchange measured (grains replicated): a position and a velocity")
          + f"), k = {allreduces:.3g} allreduces per DEM step, alpha = {ALPHA_S * 1e6:.0f} us, "
          f"beta = {BETA_B_PER_S / 1e9:.0f} GB/s per rank\n")
    print(f"  mesh: cells of {CELL_OVER_D_MAX:g} d_max, 5 tetrahedra a cell; before: every grain gathered and the "
          f"whole mesh's {MESH_FIELD_DOUBLES} doubles an element allreduced each fluid step; now: neither, each rank's "
          f"touched elements ({ELEMENT_RECORD_BYTES} B records) to the ranks that need them\n")
    print("| grains | ranks | layout | owned / rank | ghosts / rank | thickness / r_c | compute [ms] | ghost msgs [ms] | "
          "allreduce [ms] | before: gather + mesh allreduce [ms] | now: element records [ms] (elements sent; aligned) | "
          "efficiency before | efficiency now |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in model_rows(c_grain, ghost_bytes, allreduces, geometry):
        def eff(v):
            return f"{v:.2f}" if r["feasible"] else f"({v:.2f}: slab thinner than r_c)"
        print(f"| {r['grains']:.0e} | {r['ranks']} | {r['layout']} | "
              f"{r['owned']:.3g} | {r['ghosts']:.3g} | {r['thickness_over_rc']:.3g} | {r['compute_s'] * 1e3:.3g} | "
              f"{r['ghost_s'] * 1e3:.3g} | {r['reduce_s'] * 1e3:.3g} | "
              f"{r['gather_s'] * 1e3:.3g} + {r['mesh_before_s'] * 1e3:.3g} | "
              f"{r['mesh_now_s'] * 1e3:.3g} ({r['elements_sent']:.3g}; {r['elements_sent_aligned']:.3g}) | "
              f"{eff(r['efficiency_before'])} | {eff(r['efficiency'])} |")


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("summary", nargs="?", default=str(ROOT / "build" / "results" / "benchmarks" / "parallel_scaling.json"))
    ap.add_argument("--grain-cost", type=float, default=None,
                    help="[s] per grain-step instead of the run's (e.g. 2.65e-8: scene B on a quiet machine, "
                         "benchmarks/README.md, fdem against LIGGGHTS)")
    args = ap.parse_args()
    print_model(json.loads(Path(args.summary).read_text()), args.grain_cost)

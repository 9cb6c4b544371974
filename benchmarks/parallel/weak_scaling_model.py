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
measured allreduces per DEM step per rank. G: while every rank gathers every
grain after each fluid step (Simulation::particles() whole on every rank),
each rank receives N records of R bytes every `subcycles` DEM steps, G = N R
/ subcycles; "no gather" is the same without (output and checkpoints
gathered only when written).

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
                t_c = c_grain_s * (n + g / 2)
                t_ghost = messages * ALPHA_S + g * ghost_bytes / BETA_B_PER_S
                gather = grains * GATHER_RECORD_BYTES / SUBCYCLES / BETA_B_PER_S
                for gathered in (True, False):
                    t = t_c + t_ghost + reduce_s + (gather if gathered else 0.0)
                    rows.append(dict(grains=grains, ranks=ranks, layout=layout, gather=gathered, owned=n, ghosts=g,
                                     thickness_over_rc=thickness / r_c, feasible=feasible, compute_s=t_c,
                                     ghost_s=t_ghost, reduce_s=reduce_s, gather_s=gather if gathered else 0.0,
                                     step_s=t, efficiency=ideal / t))
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
    print("| grains | ranks | layout | gather each fluid step | owned / rank | ghosts / rank | thickness / r_c | "
          "compute [ms] | ghost msgs [ms] | allreduce [ms] | gather [ms] | efficiency |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in model_rows(c_grain, ghost_bytes, allreduces, geometry):
        eff = f"{r['efficiency']:.2f}" if r["feasible"] else f"({r['efficiency']:.2f}: slab thinner than r_c)"
        print(f"| {r['grains']:.0e} | {r['ranks']} | {r['layout']} | {'yes' if r['gather'] else 'no'} | "
              f"{r['owned']:.3g} | {r['ghosts']:.3g} | {r['thickness_over_rc']:.3g} | {r['compute_s'] * 1e3:.3g} | "
              f"{r['ghost_s'] * 1e3:.3g} | {r['reduce_s'] * 1e3:.3g} | {r['gather_s'] * 1e3:.3g} | {eff} |")


if __name__ == "__main__":
    import argparse

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("summary", nargs="?", default=str(ROOT / "build" / "results" / "benchmarks" / "parallel_scaling.json"))
    ap.add_argument("--grain-cost", type=float, default=None,
                    help="[s] per grain-step instead of the run's (e.g. 2.65e-8: scene B on a quiet machine, "
                         "benchmarks/README.md, fdem against LIGGGHTS)")
    args = ap.parse_args()
    print_model(json.loads(Path(args.summary).read_text()), args.grain_cost)

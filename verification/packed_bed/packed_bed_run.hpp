#pragma once
// The packed-bed measurement shared by the lattice bed (packed_bed_check.cpp)
// and the random bed settled by the DEM (random_bed_check.cpp): a fixed bed
// with a through-flow along z run to steady state, and Ergun (1952) for the
// superficial velocity U:
//
//   -dp/dz = 150 (1-eps)^2 mu U / (eps^3 d^2) + 1.75 (1-eps) rho U^2 / (eps^3 d)
//
// dp/dz is the least-squares slope of the nodal pressure over the nodes with
// z in [z0, z1] (the bed's interior); eps and u_z are volume means over the
// elements whose centroid lies there.
#include <functional>
#include <span>

#include "coupling/simulation.hpp"
#include "scene/scene.hpp"
#include "../support/bed_pressure_gradient.hpp"

namespace fdem::packed_bed {

struct BedRun {
  double porosity = 0.0;       // mean element porosity in the bed interior
  double porosity_spread = 0.0;  // max - min there
  double gradient = 0.0;       // -dp/dz [Pa/m], least squares over the interior nodes
  double gradient_change = 0.0;  // relative change over the last step (steadiness)
  double interstitial = 0.0;   // volume mean of u_z over the bed interior [m/s]
  // eps * mean over the band's grains of 1 / eps_e, eps_e their centre's
  // element's porosity: model B's f_d / eps_e factor over its value at the
  // band's mean porosity (1 for a uniform field).
  double grain_inverse_porosity = 0.0;
  // The same with each grain's porosity over its own volume (the element
  // porosity weighted as the grain's solid went into the elements,
  // PorosityField::grain_means): what model B's factor would be with its
  // 1 / eps taken so (tried 2026-12-03, not adopted: README).
  double grain_volume_inverse_porosity = 0.0;
  double wall_s = 0.0;
};

/// Runs `scene` (inlet at z_min) to its end with the model, the source form
/// and the inlet's superficial velocity U [m/s]; measures over [z0, z1] [m].
BedRun run_bed(Scene scene, FluidModel model, SourceForm source, double superficial_velocity, double z0, double z1);

using verification::ergun_gradient;       // support/bed_pressure_gradient.hpp
using verification::simplified_gradient;

/// The three fluid models each bed is run with, and the source form each uses
/// (the volume-averaged ones always the conservative form, coupling/source_term.hpp).
struct ModelSpec {
  const char* name;
  FluidModel model;
  SourceForm source;
};
inline constexpr ModelSpec kModels[] = {{"simplified", FluidModel::simplified, SourceForm::paper},
                                        {"vans_a", FluidModel::vans_a, SourceForm::conservative},
                                        {"vans_b", FluidModel::vans_b, SourceForm::conservative}};

/// One bed run of the loop below, with Ergun at its measured porosity.
struct ModelRun {
  const ModelSpec* model = nullptr;
  double reynolds = 0.0, superficial_velocity = 0.0;
  BedRun run;
  double ergun = 0.0;  // ergun_gradient at run.porosity [Pa/m]
  double ratio = 0.0;  // run.gradient / ergun
};

/// Runs `scene` with every model of kModels at each particle Reynolds number
/// Re_p = rho U d / mu (d of the scene's first particle set), prints one table
/// row per run and hands it to `check`.
void run_models(const Scene& scene, std::span<const double> reynolds, double z0, double z1,
                const std::function<void(const ModelRun&)>& check);

}  // namespace fdem::packed_bed

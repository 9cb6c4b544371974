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
#include "coupling/simulation.hpp"
#include "scene/scene.hpp"

namespace fdem::packed_bed {

struct BedRun {
  double porosity = 0.0;       // mean element porosity in the bed interior
  double porosity_spread = 0.0;  // max - min there
  double gradient = 0.0;       // -dp/dz [Pa/m], least squares over the interior nodes
  double gradient_change = 0.0;  // relative change over the last step (steadiness)
  double interstitial = 0.0;   // volume mean of u_z over the bed interior [m/s]
  double wall_s = 0.0;
};

/// Runs `scene` (inlet at z_min) to its end with the model, the source form
/// and the inlet's superficial velocity U [m/s]; measures over [z0, z1] [m].
BedRun run_bed(Scene scene, FluidModel model, SourceForm source, double superficial_velocity, double z0, double z1);

/// Ergun's -dp/dz [Pa/m] for porosity eps, superficial velocity U, grain d.
double ergun_gradient(double eps, double U, double d, double rho, double mu);

/// What the simplified model gives (div u = 0 keeps u = U in the bed, the drag
/// of Eq. 12 sees U): Ergun's viscous term times eps and its inertial term times eps^2.
double simplified_gradient(double eps, double U, double d, double rho, double mu);

}  // namespace fdem::packed_bed

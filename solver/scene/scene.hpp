#pragma once
// A scene: the complete, validated description of one run (cold configuration,
// plain structs). scene/scene_loader reads it from YAML; every module reads
// only the part it needs. SI units throughout.
//
// Ownership: the scene module owns this file; a module that needs a new
// setting adds a field with its default and the loader learns the key.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "contact_laws/contact_law.hpp"
#include "core/types.hpp"
#include "coupling_terms/momentum_exchange_form.hpp"
#include "coupling_terms/porosity_scheme.hpp"
#include "coupling_terms/source_form.hpp"

namespace fdem {

enum class CouplingMode { off, fluid_to_particle, particle_to_fluid, two_way };
enum class TimeScheme { bdf1, bdf2 };

/// What the scene simulates. What is off costs nothing at run time.
struct Effects {
  bool fluid = true;
  CouplingMode coupling = CouplingMode::two_way;
  bool gravity = true;
  bool buoyancy = true;
  std::string drag = "ergun_wen_yu";  // a law registered in drag_laws/drag_law_table.cpp
  bool normal_contact = true;
  bool tangential_contact = false;
  bool rotation = false;
  bool walls = true;
};

struct Box {
  Vec3 lower = Vec3::Zero();
  Vec3 upper = Vec3::Zero();
};

enum class FaceCondition { no_slip, free_slip, inlet, outlet };

/// Fluid boundary condition on one box face (order: x_min, x_max, y_min, y_max, z_min, z_max).
struct FaceBoundary {
  FaceCondition condition = FaceCondition::no_slip;
  Vec3 velocity = Vec3::Zero();  // inlet velocity [m/s]
  double inlet_above_m = -1e300;  // inlet applies only to nodes with z above this height (channel bed)
  // The inlet velocity is the superficial velocity (flux per area, eps u): a
  // volume-averaged fluid gives the node velocity / eps, so a bed resting on
  // the inlet receives the flux asked for; the simplified model (eps = 1 in
  // its continuity) is unchanged. Off: the node takes the velocity as given.
  bool superficial = false;
};

/// How the fluid's convection term is linearized each time step.
///   picard        fully implicit: Picard iterations on the advecting velocity until
///                 |du|/|u| <= picard_tolerance (EdgeCFD-like; several solves a step).
///   extrapolated  semi-implicit BDF: advecting velocity extrapolated from the history
///                 (2u^n - u^{n-1} for BDF2, u^n for BDF1), ONE linear solve a step;
///                 keeps the scheme's order in time (second for BDF2).
enum class FluidLinearization { picard, extrapolated };
// monolithic: one coupled SUPG/PSPG system a step (fluid/fluid_solver.hpp, the
// paper's scheme); projection: velocity predictor + pressure Poisson +
// correction (fluid/projection_scheme.hpp).
enum class FluidScheme { monolithic, projection };
// simplified: the paper's Eq. 21-22 (div u = 0, the grains' force / eps as a body force);
// vans_a / vans_b: the volume-averaged Eq. 18-19, Zhou et al. 2010 set II (fluid carries
// -eps grad p + div(eps tau)) / set I (-grad p + div tau). See fluid/fluid_element.hpp.
enum class FluidModel { simplified, vans_a, vans_b };

/// The fluid's linear solver (scene key fluid.solver.linear_solver).
///   eigen_bicgstab_ilut  BiCGSTAB + incomplete LU with threshold (Eigen), one thread.
///   petsc                PETSc KSP: FGMRES + Schur fieldsplit with BoomerAMG by default; fluid.solver.petsc_options
///                        (PETSc's option syntax) override it (fluid/petsc_linear_solver.hpp).
enum class FluidLinearSolverChoice { eigen_bicgstab_ilut, petsc };

struct FluidSpec {
  double density = 1000.0;     // [kg/m^3]
  double viscosity = 1.0e-3;   // dynamic [Pa s]
  std::array<FaceBoundary, 6> faces{};
  TimeScheme time_scheme = TimeScheme::bdf2;
  FluidScheme scheme = FluidScheme::monolithic;  // scene key fluid.scheme
  // Relative residual of each linear solve: 1e-8 changes the discretization
  // error by < 1e-6 relative (verify_fluid_mms LinearTolerance1e8And1e6_*)
  // and costs ~30 % less than 1e-10.
  double linear_tolerance = 1e-8;
  int max_linear_iterations = 1000;
  int max_picard_iterations = 10;
  double picard_tolerance = 1e-8;
  FluidLinearization linearization = FluidLinearization::extrapolated;  // scene key fluid.solver.linearization
  FluidModel model = FluidModel::simplified;  // scene key fluid.model
  bool porosity_time_derivative = false;      // scene key fluid.porosity_time_derivative: d(eps)/dt in Eq. 18
  FluidLinearSolverChoice linear_solver = FluidLinearSolverChoice::eigen_bicgstab_ilut;  // fluid.solver.linear_solver
  std::string petsc_options;  // fluid.solver.petsc_options: PETSc options over the defaults ("" = defaults)
};

enum class SizeKind { fixed, uniform, normal };
struct SizeDistribution {
  SizeKind kind = SizeKind::fixed;
  double diameter = 0.0;         // fixed [m]
  double minimum = 0.0;          // uniform bounds, or normal truncation bounds [m]
  double maximum = 0.0;
  double mean = 0.0, sd = 0.0;   // normal, truncated to [minimum, maximum] by rejection
};

enum class PlacementKind { single, lattice, random, csv };
struct ParticleSet {
  std::string name;
  PlacementKind placement = PlacementKind::single;
  Vec3 position = Vec3::Zero();          // single
  Box region;                            // lattice / random
  std::array<int, 3> lattice{1, 1, 1};   // lattice counts per direction
  int count = 0;                         // random
  std::string csv_file;                  // csv: id,d,rho,x,y,z,vx,vy,vz (anchors format)
  SizeDistribution size;
  double density = 2650.0;               // [kg/m^3]
  Vec3 velocity = Vec3::Zero();
  std::uint64_t seed = 1;
};

struct ContactSpec {
  ContactLawKind law = ContactLawKind::linear_spring_dashpot;  // a law of contact_laws/contact_law_table.cpp
  double normal_stiffness = 0.0;         // Kn [N/m], Eq. 6
  double normal_damping = 0.0;           // Cn [N s/m]; or from restitution when given
  std::optional<double> restitution;     // e in (0,1]: Cn from the pair's effective mass
  double tangential_stiffness = 0.0;     // Kt [N/m], Eq. 7
  double tangential_damping = 0.0;       // Ct [N s/m]
  double friction = 0.0;                 // mu_coulomb
  bool allow_unstable_step = false;      // run even when dt_dem exceeds the stable bound
};

struct TimeSpec {
  double fluid_step = 0.0;   // [s]
  double dem_step = 0.0;     // [s]
  double end_time = 0.0;     // [s]
  int subcycles = 0;         // DEM steps per fluid step; 0 = fluid_step / dem_step
};

struct CouplingSpec {
  PorosityScheme porosity = PorosityScheme::centre;  // a scheme of coupling_terms/porosity_scheme_table.cpp
  double porosity_floor = 0.1;   // element porosity never below this (see coupling/porosity)
  std::optional<double> porosity_smoothing_length;  // [m] > 0, diffused scheme's L; unset: from the diameters below
  std::optional<double> porosity_smoothing_diameters;  // > 0, L in largest-grain diameters; unset: 2 (coupling/porosity)
  SourceForm source_form = SourceForm::paper;  // a form of coupling_terms/source_form_table.cpp
  // coupling.exchange (coupling_terms/momentum_exchange_table.cpp); the loader's default is
  // semi_implicit when fluid.model is a VANS model
  MomentumExchange exchange = MomentumExchange::explicit_drag;
  double freeze_until = 0.0;     // particles frozen and source off until this time [s] (channel flow)
};

enum class VtuFormat { binary, ascii };  // binary: appended, zlib-compressed (io/vtu_writer.hpp)

struct OutputSpec {
  std::string directory = "out";
  double vtu_interval = 0.0;     // [s]; 0 = no VTU
  VtuFormat vtu_format = VtuFormat::binary;
  double csv_interval = 0.0;     // [s]; 0 = every fluid step
  std::vector<std::string> probes;
  double checkpoint_interval = 0.0;  // [s]; 0 = none
};

struct Scene {
  std::string source_file;       // the file it was read from, for messages
  std::string title;
  Box domain;
  std::array<int, 3> cells{1, 1, 1};
  Vec3 gravity{0.0, 0.0, -9.81};
  Effects effects;
  FluidSpec fluid;
  std::vector<ParticleSet> particles;
  ContactSpec contact;
  TimeSpec time;
  CouplingSpec coupling;
  OutputSpec output;
};

}  // namespace fdem

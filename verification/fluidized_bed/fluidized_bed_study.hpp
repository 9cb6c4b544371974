#pragma once
// The liquid-fluidized bed's run and its closed forms, shared by the check
// (fluidized_bed_check.cpp: the gated tiers) and the accuracy-cost sweep
// (fluidized_bed_sweep.cpp): the grains settled by the DEM alone, then the
// inlet raised and lowered in stages as multiples of Ergun's U_mf for the
// settled bed (README.md says what is measured and why).
//
// N grains of volume V_p in a column of section A; bed height H = 2 <z>
// from the grains' mean centre height above the floor; bed porosity
// eps = 1 - N V_p / (A H); W = N V_p (rho_p - rho_f) g the buoyant weight.
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "coupling/simulation.hpp"
#include "scene/scene.hpp"

namespace fdem::fluidized_bed {

inline constexpr double kGravity = 9.81;

struct Bed {
  double d = 0, rho_p = 0, rho_f = 0, mu = 0, area = 0;
  double count = 0;
  double solid_volume() const;
  double buoyant_weight() const;  // W [N]
  double buoyant_weight_per_area() const { return buoyant_weight() / area; }
  double porosity(double height) const { return 1.0 - solid_volume() / (area * height); }
};

// Closed forms for the bed (fluidized_bed_study.cpp says where each is from).
double ergun_drop(const Bed& b, double eps, double U, double height);  // Ergun 1952 over the bed [Pa]
double ergun_umf(const Bed& b, double eps);                            // Ergun = W / A
double wen_yu_umf(const Bed& b);                                       // Wen & Yu 1966
double simplified_umf(const Bed& b, double eps);                       // the simplified model's onset
double terminal_velocity(const Bed& b);                                // isolated sphere, the drag law's Cd
double garside_al_dibouni_n(double re_t);                              // Garside & Al-Dibouni 1977, Eq. 13
double ergun_expansion_porosity(const Bed& b, double U);               // (1-eps)(rho_p-rho_f) g = Ergun(eps, U)
// Ergun summed over a porosity profile (layers of `layer_height` each) [Pa],
// and the U at which that sum equals W / A: the onset Ergun predicts for a
// bed with that measured profile instead of its mean porosity.
double profile_ergun_drop(const Bed& b, const std::vector<double>& layer_porosity, double layer_height, double U);
double profile_ergun_umf(const Bed& b, const std::vector<double>& layer_porosity, double layer_height);

/// Numerical settings a run may change from the scene file (the sweep's
/// axes); a zero or unset field keeps the scene's.
struct Settings {
  double cell_size = 0.0;  // [m], cubic cells
  bool set_porosity = false;
  PorosityScheme porosity = PorosityScheme::shape_function;
  double fluid_step = 0.0;  // [s]; the DEM step is kept, so the subcycle count follows
  bool set_exchange = false;
  MomentumExchange exchange = MomentumExchange::semi_implicit;
};

struct Stage {
  double factor = 0, velocity = 0;
  bool rising = true;
  double drop = 0, drop_sd = 0;            // Delta p [Pa] (face integrals), mean and standard deviation over the window
  double drop_nodal = 0;                   // Delta p from the faces' plain nodal means [Pa], window mean
  double drop_first = 0, drop_second = 0;  // window's first and second halves (steadiness)
  double height = 0;                       // H = 2 <z> [m], mean over the window
  double porosity = 0;
  double layered_ergun = 0;  // Ergun summed over the cell layers' porosities at the stage's end [Pa]
  double layered_simplified = 0;  // the simplified model's closed form, the same way [Pa]
  double exchange_plug_drop = 0;  // sum_e V_e beta_e U / A, window mean [Pa] (fluidized_bed_study.cpp)
  double exchange_drop = 0;       // sum_e V_e beta_e <u_z>_e / A, window mean [Pa]
  double grain_porosity = 0;      // mean over the grains of their element's porosity, window mean
  // The bed's interior, as a packed-bed experiment measures it between taps
  // (and as verification/packed_bed's random bed does): the band from a cell
  // above the floor to a cell below the bed's top less 2 d (its rough surface),
  // the top being the highest grain's top at the window's start.
  double band_lower = 0, band_upper = 0;  // [m]
  int band_planes = 0;                    // node planes inside the band
  double interior_gradient = 0;  // -dp/dz, least squares over the band's node planes (plane means as the faces'), window mean [Pa/m]
  double interior_porosity = 0;  // exact: 1 - the grains' solid inside the band (sphere-slab volumes) / its volume, window mean
  double interior_scheme_porosity = 0;  // the porosity scheme's volume mean over the band's elements, window mean
  double exact_layered_ergun = 0;  // Ergun summed over the cell layers' exact porosities, stage end [Pa]
  std::vector<double> exact_layer_porosity;  // those porosities, layer 0 at the floor (cell height each), stage end
  double layer_height = 0;                   // [m] the cell layers' height
  double grain_layered_ergun = 0;  // Ergun summed over slabs one grain diameter thick, exact porosities, stage end [Pa]
  // The bed's momentum balance, window means, each over W (fluidized_bed_study.cpp, balance()):
  double drag = 0;             // drag on the grains
  double grain_pressure = 0;   // the grains' pressure force (coupling/fluid_stress_force.hpp), z
  double fluid_pressure = 0;   // int eps_h (-dp/dz) dV: what the fluid's pressure carries
  double solid_pressure = 0;   // int (1 - eps_h)(-dp/dz) dV
  double floor_load = 0;       // 1 - drag - grain_pressure: what the floor carries (frictionless side walls)
  double pressure_integral = 0;  // int (-dp/dz) dV = fluid + solid
};

/// The grains' exact solid volume between the planes z = a and z = b
/// (each sphere's part by its two spherical caps; the grains lie inside the
/// column's side walls, so nothing is cut off sideways) [m^3].
double slab_solid_volume(const Particles& grains, double a, double b);

struct BedRun {
  std::string model;
  std::vector<Stage> stages;
  long outside = 0;  // grains outside the mesh at any sample
  double wall_s = 0;
};

struct Prepared {
  Scene scene;
  Bed bed;
  double settled_height = 0, settled_porosity = 0, umf_ergun = 0, settle_speed = 0;
  std::vector<double> factors, velocities;
};

/// Loads `scene_file`, settles its grains for `dry_settle_s` by the DEM alone
/// (a particle CSV in the study's results folder named by `tag`), and returns
/// the coupled scene with that bed, `model`, `form` and `settings`, and the
/// stage velocities factors x Ergun's U_mf of the settled bed.
Prepared prepare(const std::string& scene_file, double dry_settle_s, FluidModel model, SourceForm form,
                 const Settings& settings, const std::vector<double>& factors, const std::string& tag);

/// Runs the stages: a packed stage after a packed one lasts `packed_s`, any
/// other `moving_s` (or packed_s for a bed that stays packed); the second half
/// of each stage is averaged.
BedRun run_stages(const Prepared& p, const std::string& model, double packed_s, double moving_s,
                  bool bed_stays_packed = false);

/// Least-squares fit of Delta p = a U + b U^2 (Ergun's form, through the
/// origin) to the stages; the U where it meets `plateau`.
double onset_velocity(const std::vector<Stage>& packed, double plateau);

std::vector<Stage> select(const std::vector<Stage>& s, bool rising, bool packed);

/// What the sweep and the check both report of model A's run.
struct Summary {
  double packed_over_ergun_worst = 1;  // rising packed stages, Ergun at each stage's eps
  double plateau_over_weight_worst = 1;  // fluidized stages over W / A
  double plateau_mean = 0;             // [Pa]
  double umf_curve = 0;                // [m/s]
  double umf_curve_over_ergun = 1;     // over Ergun's U_mf at the first stage's eps
};
Summary summarize(const BedRun& run, const Bed& bed);

}  // namespace fdem::fluidized_bed

#pragma once
// Channel flow over a particle bed (paper Sect. 4.3, Fig. 18-21, Table 3):
// the pieces of the study. Case "wall": no particles, no-slip bottom, inlet
// over the whole height. Case "bed": the same channel over a bed of 4800
// grains settled by our DEM, inlet above the bed only. The outlet profile
// u(z) (nodes of the face x = x_max, averaged over y) and its near-bed slope
// are compared between the two.
#include <string>
#include <vector>

#include "core/particles.hpp"
#include "scene/scene.hpp"

namespace fdem {
class Simulation;
}

namespace fdem::channel {

// The paper's contact set (Table 3) and the study's stable one. Scaling Kn by
// a and Cn by sqrt(a) keeps every pair's damping ratio
// zeta = Cn / (2 sqrt(Kn m_eff)), hence its restitution, while the contact
// time grows by 1/sqrt(a). At the paper's DEM step 1e-5 s the solver's
// dashpot bound m_eff / Cn for the smallest pair (0.2 mm, m_eff 4.54e-9 kg)
// allows at most Kn = 30 N/m under this scaling (its spring bound
// sqrt(m_eff / Kn) allows 45 N/m); 20 N/m gives a bound of 1.24e-5 s, a 24 %
// margin over the step.
inline constexpr double kPaperStiffness_N_m = 1.0e5;
inline constexpr double kPaperDamping_N_s_m = 0.026;
inline constexpr double kPaperDemStep_s = 1.0e-5;
inline constexpr double kStudyStiffness_N_m = 20.0;

/// The study's base scene (verification/channel/channel.yaml).
Scene base_scene();

/// Cn scaled with sqrt(Kn) from the paper's set: same damping ratio per pair.
double damping_for_stiffness(double stiffness_n_m);

/// The base scene with the paper's Kn, Cn and DEM step (refused by the solver).
Scene paper_contact_scene();

struct BedStats {
  double top_m = 0.0;                   // highest grain top, max(z + d/2)
  double max_overlap_over_diameter = 0.0;
  double kinetic_energy_j = 0.0;
  std::size_t contacts = 0;
  std::size_t particles = 0;
  double settle_time_s = 0.0;
  double wall_time_s = 0.0;
};

/// Dry DEM settling of the base scene's grains (random placement, gravity,
/// buoyancy off, the study's contact set, DEM step of the scene) for
/// `settle_time_s`. Writes the bed as csv (id,d,rho,x,y,z) to `csv_path`.
BedStats settle_bed(const Scene& base, double settle_time_s, const std::string& csv_path);

/// Case scenes. `bed_csv` empty: the wall case (no particles, inlet above 0).
Scene wall_case(const Scene& base, double end_time_s);
Scene bed_case(const Scene& base, double end_time_s, const std::string& bed_csv, double bed_top_m);

struct Profile {
  std::vector<double> z_m, u_mps;  // nodes of x = x_max, u averaged over y
};
Profile outlet_profile(const Simulation& sim);

/// Near-bed slope. The line u = u_from + dudz (z - z_from) fitted by least
/// squares to the profile nodes in [z_from, z_from + band]; slope_deg is its
/// angle to the velocity axis in the paper's plot units (u in mm/s, z in mm):
/// atan(1 / dudz[1/s]). A slower near-bed flow (smaller dudz) gives a larger
/// angle; for equal shear stress the angle ratio is the ratio of effective
/// viscosities the paper quotes.
struct Slope {
  double z_from_m = 0.0, z_to_m = 0.0;
  double dudz_1ps = 0.0;
  double u_at_z_from_mps = 0.0;
  double slope_deg = 0.0;
};
Slope near_bed_slope(const Profile& profile, double z_from_m, double band_m);

struct CaseRun {
  Profile profile;
  std::vector<double> t_s, u_probe_mps;   // u at the first profile node above z_probe, every 0.05 s
  long floored_element_updates = 0;
  long floored_elements_last = 0;
  double min_porosity = 1.0;              // smallest before the floor, over the run
  double max_overlap_over_diameter = 0.0; // over the run
  std::size_t particles_removed = 0;
  double max_momentum_imbalance = 0.0;
  double wall_time_s = 0.0;
};
/// Runs a case scene to its end, probing u at the outlet node above z_probe_m.
CaseRun run_case(const Scene& scene, double z_probe_m);

// ---- The largest stable fluid step on the bed (explicit vs semi-implicit exchange)

/// One short run of a bed case at a fluid step: stable when the solver
/// neither fails nor lets any fluid speed exceed kUnstableSpeed_m_s (twice
/// the 30 mm/s inflow: the bed can only slow the flow it is given) at any
/// step, and no grain leaves.
inline constexpr double kUnstableSpeed_m_s = 0.06;
struct StepProbe {
  double fluid_step_s = 0.0;
  bool stable = false;
  double max_speed_m_s = 0.0;  // largest nodal fluid speed over the run
  long steps = 0;              // fluid steps taken (up to a failure)
  double wall_time_s = 0.0;
  std::string failure;         // empty, "speed", "grains lost" or the solver's message
};
/// The bed scene at `fluid_step_s` with `exchange`, no freeze (the inflow
/// starts on the bed at once), run for max(coupled_time_s, 5 steps).
StepProbe probe_fluid_step(const Scene& bed_scene, double fluid_step_s, MomentumExchange exchange,
                           double coupled_time_s);

struct StableStep {
  double largest_stable_s = 0.0;    // 0: none stable in the range
  double smallest_unstable_s = 0.0; // 0: all stable up to hi_s
  std::vector<StepProbe> probes;    // in the order run
};
/// Bisection in log(dt) over [lo_s, hi_s] (each step a whole number of DEM
/// steps), `bisections` halvings after testing both ends.
StableStep largest_stable_fluid_step(const Scene& bed_scene, MomentumExchange exchange, double lo_s, double hi_s,
                                     int bisections, double coupled_time_s);

/// The explicit exchange's bound from the bed's largest drag coefficient:
/// BDF2 with the drag lagged one step, rho du/dt = -beta u^n, is stable for
/// dt beta / rho < 4 (the roots of 3 z^2 + (2 dt beta / rho - 4) z + 1 = 0
/// reach z = -1 at 4). beta_max [kg/(m^3 s)] is the largest element beta_e
/// of the settled bed at rest (coupling/momentum_exchange.hpp, conservative form).
struct ExplicitBound {
  double beta_max = 0.0, beta_median = 0.0;
  double step_s = 0.0;  // 4 rho / beta_max
};
ExplicitBound explicit_step_bound(const Scene& bed_scene);

}  // namespace fdem::channel

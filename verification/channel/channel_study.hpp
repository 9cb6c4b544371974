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

}  // namespace fdem::channel

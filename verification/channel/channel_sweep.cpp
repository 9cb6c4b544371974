// fdem_channel_sweep: the channel study's outlet slopes under changes of
// fluid model, exchange, fluid step and mesh (README.md, "Sensitivity of the
// slopes"). Each variant is channel.yaml with named overrides; the bed is the
// study's dry-settled bed (settled once, reused by every variant). Every
// case's profile is fitted over several bands, so the fit band's effect needs
// no extra run.
//
//   fdem_channel_sweep --variant paper_step_simplified --end-time 1.0   one variant (both cases)
//   fdem_channel_sweep --all --end-time 5                                 every variant (nightly)
//
// Writes $FDEM_RESULTS_DIR/channel_sweep/: profile_<variant>_<case>.csv and
// slopes_<variant>.csv (one row per case and band), and prints a table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "channel_study.hpp"
#include "core/error.hpp"
#include "core/exit_codes.hpp"
#include "io/atomic_file.hpp"
#include "scene/scene_overrides.hpp"
#include "study_io.hpp"

namespace fdem::channel {
namespace {

struct Variant {
  std::string name;
  std::vector<SceneOverride> overrides;  // on channel.yaml
  bool wall_only = false;                // no bed case (the domain does not hold the bed)
};

// The paper's fluid step (Table 3) needs the semi-implicit exchange on this
// bed (README.md, "Largest stable fluid step"); the study's explicit 5e-4 s
// is the reference the others are read against.
const SceneOverride kPaperStep{"time.fluid_step", "5.0e-3", "the paper's fluid step (Table 3)"};
const SceneOverride kSemiImplicit{"coupling.exchange", "semi_implicit", "stable at the paper's fluid step"};
const SceneOverride kFineMesh{"mesh.cell_size", "0.0003", "half the study's 0.6 mm cells"};
SceneOverride model(const std::string& m) { return {"fluid.model", m, "the fluid model under comparison"}; }

std::vector<Variant> variants() {
  return {
      {"study_explicit", {}},
      {"study_step_semi_implicit", {kSemiImplicit, model("simplified")}},
      {"paper_step_simplified", {kPaperStep, kSemiImplicit, model("simplified")}},
      {"paper_step_vans_a", {kPaperStep, kSemiImplicit, model("vans_a")}},
      {"paper_step_vans_b", {kPaperStep, kSemiImplicit, model("vans_b")}},
      {"fine_study_explicit", {kFineMesh}},
      {"fine_paper_step_simplified", {kFineMesh, kPaperStep, kSemiImplicit, model("simplified")}},
      {"fine_paper_step_vans_a", {kFineMesh, kPaperStep, kSemiImplicit, model("vans_a")}},
      // The bed as an impermeable wall: the wall case with its floor at the
      // settled bed's top (3.3 mm, a whole number of 0.3 mm cells below the
      // 12 mm top; the bed's top is 3.295 mm), so the same inflow crosses the
      // same 8.7 mm gap over a no-slip floor.
      {"fine_wall_at_bed_top",
       {kFineMesh, kPaperStep, kSemiImplicit,
        {"domain.lower", "[0, 0, 0.0033]", "the floor at the bed's top: an impermeable bed"},
        {"particles[0].region.lower", "[0, 0, 0.0033]", "inside the cut domain (the wall case has no grains)"}},
       true},
  };
}

// Fit bands [m] from the wall or from the first node at or above the bed top.
constexpr double kBands_m[] = {0.3e-3, 0.6e-3, 1.2e-3, 1.8e-3, 2.4e-3};

double first_node_at_or_above(const Profile& p, double z_m) {
  for (double z : p.z_m)
    if (z >= z_m - 1e-9) return z;
  throw std::runtime_error("no profile node above the bed");
}

double unsteadiness(const CaseRun& c) {
  if (c.t_s.size() < 6) return INFINITY;
  return std::abs(c.u_probe_mps.back() - c.u_probe_mps[c.u_probe_mps.size() - 6]) / std::abs(c.u_probe_mps.back());
}

struct Row {
  std::string variant, kase;
  double band_m, z_from_m, z_to_m, dudz_1ps, slope_deg;
  int nodes;
};

// A case's health, gated when the sweep is asked to (the nightly tier):
// no grain lost, overlaps below 1 % d (the study's gate, test_channel.cpp),
// the near-bed velocity steady within `steady_within` over the last 0.25 s.
std::vector<std::string> health_failures(const std::string& what, const CaseRun& r, double steady_within) {
  std::vector<std::string> out;
  if (r.particles_removed > 0) out.push_back(fmt::format("{}: {} grains lost", what, r.particles_removed));
  if (r.max_overlap_over_diameter >= 0.01)
    out.push_back(fmt::format("{}: overlap {:.3g} % d", what, 100 * r.max_overlap_over_diameter));
  if (steady_within > 0.0 && !(unsteadiness(r) < steady_within))
    out.push_back(fmt::format("{}: near-bed velocity moved {:.3g} over the last 0.25 s (bound {})", what,
                              unsteadiness(r), steady_within));
  return out;
}

void run_variant(const Variant& v, double end_time_s, const std::string& bed_csv, double bed_top_m,
                 const std::string& dir, std::vector<Row>& rows, double steady_within,
                 std::vector<std::string>& failures) {
  const std::string yaml = std::string(FDEM_SOURCE_DIR) + "/verification/channel/channel.yaml";
  const Scene base = load_scene_with_overrides(yaml, v.overrides);
  const double h = (base.domain.upper.z() - base.domain.lower.z()) / base.cells[2];
  for (const bool bed : {false, true}) {
    if (bed && v.wall_only) continue;
    const std::string kase = bed ? "bed" : "wall";
    const Scene scene = bed ? bed_case(base, end_time_s, bed_csv, bed_top_m) : wall_case(base, end_time_s);
    const double probe_z = bed ? std::ceil(bed_top_m / h - 1e-9) * h : h;
    const CaseRun r = run_case(scene, probe_z);
    for (std::string& f : health_failures(v.name + " " + kase, r, steady_within)) failures.push_back(std::move(f));
    std::vector<std::vector<double>> profile;
    for (std::size_t i = 0; i < r.profile.z_m.size(); ++i) profile.push_back({r.profile.z_m[i], r.profile.u_mps[i]});
    study::write_numeric_csv(dir + "/profile_" + v.name + "_" + kase + ".csv", {"z_m", "u_mps"}, profile,
                             {fmt::format("outlet profile, variant {}, {} case, t = {} s", v.name, kase, end_time_s)});
    const double z_from = bed ? first_node_at_or_above(r.profile, bed_top_m) : 0.0;
    for (const double band : kBands_m) {
      if (band < h - 1e-12) continue;  // fewer than 2 nodes
      const Slope s = near_bed_slope(r.profile, z_from, band);
      rows.push_back({v.name, kase, band, s.z_from_m, s.z_to_m, s.dudz_1ps, s.slope_deg,
                      static_cast<int>(std::lround((s.z_to_m - s.z_from_m) / h)) + 1});
    }
    std::printf("%s %s: cell %.2g mm, dt %.1e s, %s, %s exchange: %.1f s wall, unsteadiness %.2g, floor updates %ld, "
                "min porosity %.3f, max overlap %.3f %% d, lost %zu\n",
                v.name.c_str(), kase.c_str(), 1e3 * h, scene.time.fluid_step,
                scene.fluid.model == FluidModel::simplified ? "simplified" :
                scene.fluid.model == FluidModel::vans_a     ? "vans_a"     : "vans_b",
                std::string(momentum_exchange_entry(scene.coupling.exchange).name).c_str(),
                r.wall_time_s, unsteadiness(r), r.floored_element_updates, r.min_porosity,
                100 * r.max_overlap_over_diameter, r.particles_removed);
    std::fflush(stdout);
  }
}

// slopes_<name>.csv: one row per case and band.
void write_rows(const std::string& path, const std::vector<Row>& rows, double end_time_s) {
  std::string csv = fmt::format("# channel slopes under overrides of channel.yaml, t = {} s; slope_deg = atan(1 / "
                                "dudz[1/s]) (README.md)\n",
                                end_time_s);
  csv += "variant,case,band_m,nodes,z_from_m,z_to_m,dudz_1ps,slope_deg\n";
  for (const Row& r : rows)
    csv += fmt::format("{},{},{},{},{},{},{},{}\n", r.variant, r.kase, r.band_m, r.nodes, r.z_from_m, r.z_to_m,
                       r.dudz_1ps, r.slope_deg);
  write_file_atomically(path, csv);
}

void print_table(const std::vector<Row>& rows) {
  std::printf("\n%-28s %8s %6s %10s %10s %8s\n", "variant", "band mm", "nodes", "wall deg", "bed deg", "ratio");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].kase != "bed") continue;
    for (const Row& w : rows)
      if (w.kase == "wall" && w.variant == rows[i].variant && std::abs(w.band_m - rows[i].band_m) < 1e-12)
        std::printf("%-28s %8.2f %6d %10.3f %10.3f %8.3f\n", rows[i].variant.c_str(), 1e3 * rows[i].band_m,
                    rows[i].nodes, w.slope_deg, rows[i].slope_deg, rows[i].slope_deg / w.slope_deg);
  }
}

}  // namespace
}  // namespace fdem::channel

int main(int argc, char** argv) {
  CLI::App app{"channel study: slopes under changes of model, exchange, fluid step and mesh"};
  std::vector<std::string> names;
  bool all = false;
  double end_time_s = 1.0;
  app.add_option("--variant", names, "variant(s) to run (see --list)");
  app.add_flag("--all", all, "run every variant");
  app.add_option("--end-time", end_time_s, "end time [s]; 1.0 gives the 5 s slopes within 0.2 % (README.md)");
  bool list = false;
  app.add_flag("--list", list, "print the variants and exit");
  double steady_within = 0.0;
  app.add_option("--steady-within", steady_within,
                 "fail (exit 1) unless every case's near-bed velocity moved less than this over the last 0.25 s");
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  using namespace fdem::channel;
  if (list) {
    for (const Variant& v : variants()) {
      std::string text;
      for (const fdem::SceneOverride& o : v.overrides) text += fmt::format(" {}={}", o.key, o.value);
      std::printf("%s:%s\n", v.name.c_str(), text.empty() ? " (channel.yaml as it is)" : text.c_str());
    }
    return 0;
  }
  return fdem::run_with_exit_codes("fdem_channel_sweep", [&] {
    std::vector<Variant> chosen;
    for (const Variant& v : variants())
      if (all || std::find(names.begin(), names.end(), v.name) != names.end()) chosen.push_back(v);
    if (chosen.size() != (all ? variants().size() : names.size()))
      throw fdem::InputError("--variant", "variant", fmt::format("{}", fmt::join(names, ",")),
                             "unknown variant (fdem_channel_sweep --list)");
    const std::string dir = fdem::study::results_dir("channel_sweep");
    std::filesystem::create_directories(dir);
    const std::string bed_csv = std::string(FDEM_BINARY_DIR) + "/verification/channel/bed_settled_sweep_" +
                                (all ? std::string("all") : names.front()) + ".csv";
    const fdem::Scene base = base_scene();
    const BedStats bed = settle_bed(base, 0.1, bed_csv);  // the study's settling (test_channel.cpp, kSettleTime_s)
    std::printf("bed: %zu grains, top %.4g mm, %.1f s\n", bed.particles, 1e3 * bed.top_m, bed.wall_time_s);
    std::vector<Row> rows;
    std::vector<std::string> failures;
    for (const Variant& v : chosen) {
      std::vector<Row> own;
      run_variant(v, end_time_s, bed_csv, bed.top_m, dir, own, steady_within, failures);
      write_rows(dir + "/slopes_" + v.name + ".csv", own, end_time_s);
      rows.insert(rows.end(), own.begin(), own.end());
    }
    print_table(rows);
    for (const std::string& f : failures) std::fprintf(stderr, "FAIL %s\n", f.c_str());
    return failures.empty() ? 0 : 1;
  });
}

#include "scene/time_steps.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace fdem {

namespace {

constexpr int kMaxSubcycles = 100000000;  // 1e8: beyond it a fluid step is a typo, not a plan

}  // namespace

TimeSpec resolve_time_steps(const Scene& scene, const std::optional<MassRange>& masses,
                            const RefuseTimeStep& refuse) {
  TimeSpec t = scene.time;
  const auto fail = [&](const std::string& key, const std::string& reason) {
    refuse(key, reason);
    throw InputError(scene.source_file, "time." + key, "", reason);  // refuse() must throw; this never runs
  };
  if (t.subcycles < 0 || t.subcycles > kMaxSubcycles)
    fail("subcycles", "must lie in [1, 1e8] (0 or absent: derived)");
  if (t.dem_step < 0.0) fail("dem_step", "time step must be > 0 [s]");
  if (!scene.effects.fluid && t.fluid_step <= 0.0) {  // dry scene: the driver step is subcycles DEM steps
    if (t.dem_step <= 0.0) fail("dem_step", "time step must be > 0 [s]");
    t.fluid_step = t.dem_step * static_cast<double>(std::max(t.subcycles, 1));
  }
  if (!(t.fluid_step > 0.0)) fail("fluid_step", "time step must be > 0 [s]");

  if (t.dem_step <= 0.0 && t.subcycles > 0) t.dem_step = t.fluid_step / t.subcycles;
  if (t.dem_step <= 0.0) {
    if (masses) {  // the largest stable DEM step that divides the fluid step
      const double stable =
          analyse_stability(scene.contact, scene.effects, *masses, t.fluid_step, scene.effects.walls).stable_step_s();
      const int n = std::max(1, static_cast<int>(std::ceil(t.fluid_step / stable - 1e-9)));
      t.dem_step = t.fluid_step / n;
    } else if (scene.particles.empty()) {
      t.dem_step = t.fluid_step;  // nothing to subcycle
    } else {
      fail("dem_step", "required with particles: give dem_step or subcycles");
    }
  }

  const double ratio = t.fluid_step / t.dem_step;
  if (ratio < 1.0 - 1e-9) fail("dem_step", fmt::format("DEM step exceeds the fluid step {} s", t.fluid_step));
  const double whole = std::round(ratio);
  if (whole > kMaxSubcycles) fail("dem_step", "more than 1e8 DEM subcycles per fluid step");
  if (t.subcycles > 0) {
    if (std::abs(static_cast<double>(t.subcycles) * t.dem_step - t.fluid_step) > 1e-9 * t.fluid_step)
      fail("subcycles", fmt::format("subcycles x dem_step = {} s differs from fluid_step = {} s",
                                    static_cast<double>(t.subcycles) * t.dem_step, t.fluid_step));
  } else {
    if (std::abs(ratio - whole) > 1e-6 * whole)
      fail("dem_step", fmt::format("fluid_step / dem_step = {} is not a whole number of subcycles", ratio));
    t.subcycles = static_cast<int>(whole);
  }
  if (masses) require_stable_dem_step(scene, *masses, t.dem_step);
  return t;
}

void require_stable_dem_step(const Scene& scene, const MassRange& masses, double dem_step) {
  if (!scene.effects.normal_contact) return;
  const StabilityReport report = analyse_stability(scene.contact, scene.effects, masses, dem_step, scene.effects.walls);
  require_stable_step(report, scene.contact, scene.source_file);
}

}  // namespace fdem

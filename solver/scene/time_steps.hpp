#pragma once
// The time steps of a run, resolved in one place (paper Sect. 2.3, Fig. 2-3:
// every fluid step holds `subcycles` DEM steps). The loader resolves each
// scene file with it, Simulation each scene it is given (so scenes built in
// code follow the same rules), `fdem check` prints what it resolved, and
// DemEngine asserts the stability bound it was given through
// require_stable_dem_step.
//
// Rules (TimeSpec: 0 = not given), each broken one refused naming its key
// under `time.`:
//   fluid_step  > 0 with fluid; a dry scene without one steps subcycles
//               (default 1) DEM steps per step
//   dem_step    > 0; without it, fluid_step / subcycles when subcycles is
//               given, else (scenes built in code: a file must give it when
//               it has particles) the largest stable DEM step that divides
//               the fluid step, or the fluid step when there are no particles
//   subcycles   in [0, 1e8]; given: subcycles x dem_step = fluid_step to 1e-9
//               relative (decimal steps such as 1e-3 / 1e-5 are exact to
//               ~1e-16); derived: fluid_step / dem_step within 1e-6 of a
//               whole number in [1, 1e8]
//   stability   dem_step within the bound of scene/stability.hpp for the
//               run's particles, unless contact.allow_unstable_step
#include <functional>
#include <optional>
#include <string>

#include "scene/scene.hpp"
#include "scene/stability.hpp"

namespace fdem {

/// Called with the key under `time.` and the reason of a broken rule; must
/// throw (the loader adds the file's line and value, Simulation the value).
using RefuseTimeStep = std::function<void(const std::string& key, const std::string& reason)>;

/// `scene.time` resolved: fluid_step, dem_step and subcycles all set.
/// `masses`: the mass range of the particles the run holds; nullopt when
/// there are none, or when they are not known yet (the loader: then the
/// stability bound is left to Simulation, and a scene with particles must
/// give dem_step or subcycles).
TimeSpec resolve_time_steps(const Scene& scene, const std::optional<MassRange>& masses,
                            const RefuseTimeStep& refuse);

/// Throws InputError naming scene.source_file, time.dem_step and its value
/// when `dem_step` is above the stability bound for `masses`
/// (scene/stability.hpp) and contact.allow_unstable_step is false. Nothing
/// without normal contact.
void require_stable_dem_step(const Scene& scene, const MassRange& masses, double dem_step);

}  // namespace fdem

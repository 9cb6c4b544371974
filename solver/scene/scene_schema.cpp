#include "scene/scene_schema.hpp"

#include <algorithm>
#include <array>
#include <deque>

#include <fmt/format.h>

#include "contact_laws/contact_law.hpp"
#include "coupling_terms/momentum_exchange_form.hpp"
#include "coupling_terms/porosity_scheme.hpp"
#include "coupling_terms/source_form.hpp"
#include "drag_laws/drag_law.hpp"

namespace fdem {

namespace {

constexpr std::array<std::string_view, 6> kFaces{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};

// One row per key. Types and defaults as examples/README.md states them; a
// registered term's type (and, for the coupling terms, its doc) is spelt
// from its table (kTermKeys below), so it is left empty here.
constexpr SceneKey kSchema[] = {
    {"title", "string", "\"\"", "free text"},
    {"domain", "box", "required", "the fluid box and the DEM walls [m]", true},
    {"domain.lower", "[x, y, z]", "required", "lower corner [m]"},
    {"domain.upper", "[x, y, z]", "required", "upper corner [m]; above lower on every axis"},
    {"mesh", "map", "required with fluid", "exactly one of cells, cell_size; each cell is split into 5 tetrahedra", true},
    {"mesh.cells", "[nx, ny, nz] integers >= 1", "-", "cell counts per axis"},
    {"mesh.cell_size", "number or [hx, hy, hz] > 0", "-",
     "cell edge [m]; the domain must hold a whole number of cells (1e-6 relative)"},
    {"gravity", "[x, y, z]", "[0, 0, -9.81]", "[m/s^2], switched by effects.gravity"},

    {"effects", "map", "all defaults below", "what the scene simulates; what is off costs nothing", true},
    {"effects.fluid", "bool", "true", "solve the fluid (mesh, fluid and time.fluid_step then required)"},
    {"effects.coupling", "one of: off, fluid_to_particle, particle_to_fluid, two_way", "two_way (off without fluid)",
     "which way drag acts; anything but off needs effects.fluid"},
    {"effects.gravity", "bool", "true", "gravity on the particles"},
    {"effects.buoyancy", "bool", "true with fluid, false without", "buoyancy on the particles; needs effects.fluid"},
    {"effects.drag", "", "ergun_wen_yu",
     "drag law: Ergun / Wen & Yu with Rowe & Henwood Cd (Eq. 11-15), 3 pi mu d (u - v), or a dense-regime law; "
     "fdem check prints the law's source"},
    {"effects.normal_contact", "bool", "true", "normal contact by contact.law (Eq. 6)"},
    {"effects.tangential_contact", "bool", "false",
     "tangential spring-dashpot with Coulomb cap (Eq. 7-8); needs normal_contact and contact.kt > 0"},
    {"effects.rotation", "bool", "false", "particle rotation and torque (Eq. 10)"},
    {"effects.walls", "bool", "true", "the six domain faces are DEM walls"},

    {"fluid", "map", "required with fluid", "fluid properties and solver", true},
    {"fluid.density", "number > 0", "required", "[kg/m^3]"},
    {"fluid.viscosity", "number > 0", "required", "dynamic viscosity [Pa s]"},
    {"fluid.time_scheme", "one of: bdf1, bdf2", "bdf2", "time integration of the fluid"},
    {"fluid.scheme", "one of: monolithic, projection", "monolithic",
     "monolithic: one SUPG/PSPG system a step (the paper's); projection: predictor, pressure Poisson, correction "
     "(simplified model, one rank, no steady solve)"},
    {"fluid.model", "one of: simplified, vans_a, vans_b", "simplified",
     "simplified: Eq. 21-22 (div u = 0, drag / eps as body force); vans_a / vans_b: volume-averaged Eq. 18-19, "
     "Zhou et al. 2010 set II / set I"},
    {"fluid.porosity_time_derivative", "bool", "false", "keep d(eps)/dt in Eq. 18 (vans_a and vans_b only)"},
    {"fluid.boundaries", "map", "every face no_slip", "condition on each face of the box", true},
    {"fluid.boundaries.x_min", "no_slip | free_slip | outlet, or a map", "no_slip",
     "a word, or {type: inlet, velocity: [u, v, w], above: z}"},
    {"fluid.boundaries.x_max", "as x_min", "no_slip", ""},
    {"fluid.boundaries.y_min", "as x_min", "no_slip", ""},
    {"fluid.boundaries.y_max", "as x_min", "no_slip", ""},
    {"fluid.boundaries.z_min", "as x_min", "no_slip", ""},
    {"fluid.boundaries.z_max", "as x_min", "no_slip", ""},
    {"fluid.boundaries.<face>", "map", "-", "a face given as a map", true},
    {"fluid.boundaries.<face>.type", "one of: no_slip, free_slip, inlet, outlet", "required", "the condition"},
    {"fluid.boundaries.<face>.velocity", "[u, v, w]", "required for inlet", "inlet velocity [m/s]"},
    {"fluid.boundaries.<face>.above", "number", "everywhere", "the inlet applies only to nodes above this height [m]"},
    {"fluid.boundaries.<face>.superficial", "bool", "false",
     "the inlet velocity is superficial (eps u): a VANS fluid gives each inlet node velocity / eps (a bed on the inlet)"},
    {"fluid.solver", "map", "defaults below", "the linear and nonlinear solves of each fluid step", true},
    {"fluid.solver.linear_tolerance", "number in (0, 1)", "1e-8", "relative residual of each linear solve"},
    {"fluid.solver.max_linear_iterations", "integer in [1, 1e7]", "1000", "linear-solver iterations per solve"},
    {"fluid.solver.picard_tolerance", "number in (0, 1)", "1e-8", "|du|/|u| that ends the Picard iterations"},
    {"fluid.solver.max_picard_iterations", "integer in [1, 10000]", "10", "Picard iterations per step"},
    {"fluid.solver.linearization", "one of: picard, extrapolated", "extrapolated",
     "extrapolated: advecting velocity from the history, one solve a step; picard: iterate to picard_tolerance"},
    {"fluid.solver.linear_solver", "one of: eigen_bicgstab_ilut, petsc", "eigen_bicgstab_ilut",
     "eigen_bicgstab_ilut: Eigen's BiCGSTAB + ILUT; petsc: PETSc FGMRES, Schur fieldsplit, hypre BoomerAMG"},
    {"fluid.solver.petsc_options", "string of PETSc options", "\"\"",
     "only with petsc: options over fluid/petsc_linear_solver.hpp's defaults; an unused one stops the run"},

    {"particles", "list of maps", "none", "particle sets, generated in list order"},
    {"particles[]", "map", "-", "one particle set", true},
    {"particles[].name", "string", "set<i>", "unique among sets"},
    {"particles[].placement", "one of: single, lattice, random, csv", "required", "how the set is placed"},
    {"particles[].position", "[x, y, z]", "required for single", "centre [m]; the whole sphere inside the domain"},
    {"particles[].region", "box", "required for lattice, random", "inside the domain", true},
    {"particles[].region.lower", "[x, y, z]", "required", "lower corner [m]"},
    {"particles[].region.upper", "[x, y, z]", "required", "upper corner [m]"},
    {"particles[].lattice", "[nx, ny, nz] integers >= 1", "required for lattice",
     "sites at the centres of equal sub-boxes, x fastest; spacing >= the largest diameter"},
    {"particles[].count", "integer in [1, 1e8]", "required for random",
     "non-overlapping, uniform in the region; at most half the region filled"},
    {"particles[].file", "path", "required for csv", "id,d,rho,x,y,z[,vx,vy,vz] rows, relative to the scene file"},
    {"particles[].size", "number or map", "required (not for csv)", "a number is a fixed diameter [m]", true},
    {"particles[].size.distribution", "one of: fixed, uniform, normal", "fixed", "the diameter distribution"},
    {"particles[].size.diameter", "number > 0", "required for fixed", "[m]"},
    {"particles[].size.min", "number > 0", "required for uniform, normal", "smallest diameter (normal: truncation) [m]"},
    {"particles[].size.max", "number > min", "required for uniform, normal", "largest diameter [m]"},
    {"particles[].size.mean", "number > 0", "required for normal", "mean diameter [m]"},
    {"particles[].size.sd", "number > 0", "required for normal",
     "standard deviation [m]; [min, max] must hold >= 1e-3 of the distribution"},
    {"particles[].density", "number > 0", "required (not for csv)", "[kg/m^3]"},
    {"particles[].velocity", "[u, v, w]", "[0, 0, 0]", "initial velocity [m/s]"},
    {"particles[].seed", "integer >= 0", "1", "seeds the set's generator: same scene, same particles"},

    {"contact", "map", "required with particles and normal contact", "the contact law and its coefficients (Eq. 6-10)",
     true},
    {"contact.law", "", "linear_spring_dashpot", ""},
    {"contact.kn", "number > 0", "required with particles and normal contact", "normal stiffness Kn [N/m]"},
    {"contact.cn", "number >= 0", "0", "normal damping Cn [N s/m]; give cn or restitution, not both"},
    {"contact.restitution", "number in (0, 1]", "none", "Cn from e for each pair's effective mass"},
    {"contact.kt", "number >= 0", "0", "tangential stiffness Kt [N/m] (Eq. 7)"},
    {"contact.ct", "number >= 0", "0", "tangential damping Ct [N s/m]"},
    {"contact.friction", "number >= 0", "0", "Coulomb coefficient"},
    {"contact.allow_unstable_step", "bool", "false",
     "run although time.dem_step exceeds the stable bound (fdem check prints it)"},

    {"time", "map", "required", "time steps and end time", true},
    {"time.fluid_step", "number > 0", "required with fluid; else subcycles x dem_step", "[s]"},
    {"time.dem_step", "number > 0", "required with particles", "[s]; a whole number of subcycles per fluid_step"},
    {"time.subcycles", "integer", "fluid_step / dem_step", "DEM steps per fluid step; if given, x dem_step = fluid_step"},
    {"time.end", "number >= fluid_step", "required", "end time [s]; at most 1e9 steps"},

    {"coupling", "map", "defaults below", "the FEM-DEM exchange", true},
    {"coupling.porosity", "", "centre", ""},
    {"coupling.porosity_floor", "number in (0, 1)", "0.1", "element porosity never below this"},
    {"coupling.porosity_smoothing_length", "number > 0", "from porosity_smoothing_diameters",
     "[m] smoothing length of diffused; capped by the bed (coupling/porosity.hpp)"},
    {"coupling.porosity_smoothing_diameters", "number > 0", "2",
     "smoothing length of diffused in largest-grain diameters; not with porosity_smoothing_length"},
    {"coupling.source_form", "", "paper; conservative with fluid.model vans_a / vans_b", ""},
    {"coupling.exchange", "", "explicit; semi_implicit with fluid.model vans_a / vans_b", ""},
    {"coupling.freeze_until", "number in [0, time.end]", "0", "[s] particles frozen and source off until then"},

    {"output", "map", "defaults below", "what fdem run writes", true},
    {"output.directory", "string", "out", "output folder; fdem run --output overrides it"},
    {"output.vtu_interval", "number >= 0", "0", "[s] between VTU snapshots; 0 = none"},
    {"output.vtu_format", "one of: binary, ascii", "binary",
     "binary: appended, zlib-compressed (~1/3 the size); ascii: decimal text"},
    {"output.csv_interval", "number >= 0", "0", "[s] between probe rows; 0 = every step"},
    {"output.checkpoint_interval", "number >= 0", "0", "[s] between checkpoints; 0 = none"},
    {"output.probes", "list of probe names", "all",
     "any of count, mean_position, mean_velocity, max_speed, kinetic_energy, z_range"},
};

// The leaf keys whose own value is not in a checkpoint's scene fingerprint,
// first match wins; every other leaf key's is (scene_key_values.cpp).
constexpr FingerprintExemption kFingerprintExemptions[] = {
    {"title", "", "free text"},
    {"time.end", "", "a restart may run further than the checkpointed run"},
    {"output.", "", "where and how often a run writes changes no step"},
    {"contact.allow_unstable_step", "", "a permission to run; the step is the same"},
    {"mesh.cell_size", "mesh.cells", "resolved into the cell counts"},
    {"fluid.boundaries.x_min", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"fluid.boundaries.x_max", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"fluid.boundaries.y_min", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"fluid.boundaries.y_max", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"fluid.boundaries.z_min", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"fluid.boundaries.z_max", "fluid.boundaries.<face>.type", "a face's word resolves into its type"},
    {"particles[].name", "", "a label no step reads"},
    {"particles", "particles", "the generated particles' hash (positions, velocities, diameters, masses)"},
    {"particles[].", "particles", "the generated particles' hash (positions, velocities, diameters, masses)"},
};

bool is_face(std::string_view name) { return std::find(kFaces.begin(), kFaces.end(), name) != kFaces.end(); }

// "one of: a, b" and "a: doc of a; b: doc of b" from a registration table.
template <class Row>
std::string one_of(std::span<const Row> rows) {
  return "one of: " + row_names(rows);
}
template <class Row>
std::string each_doc(std::span<const Row> rows) {
  std::string doc;
  for (const Row& row : rows) doc += fmt::format("{}{}: {}", doc.empty() ? "" : "; ", row.name, row.doc);
  return doc;
}

// The keys whose words are a registration table's: type and doc as the
// table spells them (no doc function: the row's own doc stands).
struct TermKey {
  std::string_view path;
  std::string (*type)();
  std::string (*doc)();
};
const TermKey kTermKeys[] = {
    {"effects.drag", [] { return "a law of drag_laws/drag_law_table.cpp: " + drag_law_names(); }, nullptr},
    {"contact.law", [] { return one_of(contact_laws()); }, [] { return each_doc(contact_laws()); }},
    {"coupling.porosity", [] { return one_of(porosity_schemes()); }, [] { return each_doc(porosity_schemes()); }},
    {"coupling.source_form", [] { return one_of(source_forms()); }, [] { return each_doc(source_forms()); }},
    {"coupling.exchange", [] { return one_of(momentum_exchanges()); }, [] { return each_doc(momentum_exchanges()); }},
};

// The schema with the registered terms spelt out, built once.
struct ResolvedSchema {
  std::deque<std::string> texts;  // the spelt-out types and docs the keys view (a deque never moves them)
  std::vector<SceneKey> keys;
  ResolvedSchema() {
    for (SceneKey k : kSchema) {
      for (const TermKey& t : kTermKeys) {
        if (t.path != k.path) continue;
        k.type = texts.emplace_back(t.type());
        if (t.doc != nullptr) k.doc = texts.emplace_back(t.doc());
      }
      keys.push_back(k);
    }
  }
};

std::span<const SceneKey> schema_keys() {
  static const ResolvedSchema schema;
  return schema.keys;
}

}  // namespace

std::span<const SceneKey> scene_schema() { return schema_keys(); }

std::span<const FingerprintExemption> fingerprint_exemptions() { return kFingerprintExemptions; }

const FingerprintExemption* fingerprint_exemption(std::string_view path) {
  for (const FingerprintExemption& e : kFingerprintExemptions) {
    const bool prefix = e.path.ends_with('.');
    if (prefix ? path.starts_with(e.path) : path == e.path) return &e;
  }
  return nullptr;
}

std::string schema_path_of(std::string_view key) {
  std::string out;
  for (std::size_t i = 0; i < key.size(); ++i) {
    if (key[i] == '[') {
      const std::size_t close = key.find(']', i);
      if (close == std::string_view::npos) return std::string(key);  // not a key path
      out += "[]";
      i = close;
    } else {
      out += key[i];
    }
  }
  constexpr std::string_view boundaries = "fluid.boundaries.";
  if (out.starts_with(boundaries)) {
    const std::size_t end = out.find('.', boundaries.size());
    if (end != std::string::npos && is_face(std::string_view(out).substr(boundaries.size(), end - boundaries.size()))) {
      out.replace(boundaries.size(), end - boundaries.size(), "<face>");
    }
  }
  return out;
}

std::vector<std::string_view> choice_words(std::string_view path) {
  constexpr std::string_view kOneOf = "one of: ";
  std::vector<std::string_view> words;
  for (const SceneKey& k : schema_keys()) {
    if (k.path != path || !k.type.starts_with(kOneOf)) continue;
    std::string_view rest = k.type.substr(kOneOf.size());
    while (!rest.empty()) {
      const std::size_t comma = rest.find(", ");
      words.push_back(rest.substr(0, comma));
      rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 2);
    }
  }
  return words;
}

std::string_view choice_word(std::string_view path, std::size_t index) {
  const std::vector<std::string_view> words = choice_words(path);
  return index < words.size() ? words[index] : std::string_view("?");
}

bool is_scene_key(std::string_view key) {
  const std::string path = schema_path_of(key);
  const std::span<const SceneKey> keys = schema_keys();
  return std::any_of(keys.begin(), keys.end(), [&](const SceneKey& k) { return k.path == path; });
}

std::vector<std::string> scene_keys_below(std::string_view path) {
  // Normalise the map's own path as the head of a longer key.
  std::string parent = path.empty() ? std::string() : schema_path_of(std::string(path) + ".x");
  if (!parent.empty()) parent.resize(parent.size() - 1);  // keep the trailing dot
  std::vector<std::string> out;
  for (const SceneKey& k : schema_keys()) {
    if (!k.path.starts_with(parent)) continue;
    const std::string_view rest = k.path.substr(parent.size());
    if (rest.empty() || rest.find('.') != std::string_view::npos || rest.find('[') != std::string_view::npos) continue;
    if (rest == "<face>") continue;  // the faces are listed by name
    out.emplace_back(rest);
  }
  return out;
}

std::string format_scene_schema() {
  std::string out =
      "Scene file keys (YAML, SI units). `particles[]` is each item of the particles list, `<face>` each of\n"
      "x_min x_max y_min y_max z_min z_max. Longer explanations: examples/README.md (installed as\n"
      "share/doc/fdem/scene-files.md).\n";
  for (const SceneKey& k : schema_keys()) {
    if (k.path.find('.') == std::string_view::npos && k.path.find('[') == std::string_view::npos) out += '\n';
    out += fmt::format("{}  ({}; default: {})\n", k.path, k.type, k.default_value);
    if (!k.doc.empty()) out += fmt::format("    {}\n", k.doc);
  }
  return out;
}

}  // namespace fdem

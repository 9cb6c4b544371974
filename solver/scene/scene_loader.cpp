#include "scene/scene_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>
#include <utility>

#include <fmt/format.h>
#include <gsl/gsl_cdf.h>
#include <yaml-cpp/yaml.h>

#include "contact_laws/contact_law.hpp"
#include "core/error.hpp"
#include "core/named_rows.hpp"
#include "drag_laws/drag_law.hpp"
#include "io/probes.hpp"
#include "scene/particle_csv.hpp"
#include "scene/time_steps.hpp"

namespace fdem {

namespace {

// ---------------------------------------------------------------- messages

int line_of(const YAML::Node& node) {
  const YAML::Mark mark = node.Mark();
  return mark.line >= 0 ? mark.line + 1 : 0;  // yaml-cpp counts lines from 0
}

// The value as the user wrote it, on one short line.
std::string show(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "";
  std::string text;
  if (node.IsScalar()) {
    text = node.Scalar();
  } else {
    YAML::Emitter out;
    out << YAML::Flow << node;
    text = out.good() ? std::string(out.c_str()) : std::string("<unprintable>");
  }
  std::replace(text.begin(), text.end(), '\n', ' ');
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  return text;
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string suggestion(const std::string& key, const std::vector<std::string>& allowed) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& candidate : allowed) {
    const std::size_t d = edit_distance(key, candidate);
    if (d < best_distance) {
      best_distance = d;
      best = candidate;
    }
  }
  std::string all;
  for (const auto& candidate : allowed) all += (all.empty() ? "" : ", ") + candidate;
  if (!best.empty() && best_distance <= std::max<std::size_t>(2, best.size() / 3)) {
    return fmt::format("unknown key; did you mean '{}'? (valid: {})", best, all);
  }
  return fmt::format("unknown key (valid: {})", all);
}

// ---------------------------------------------------------------- reading

// One YAML mapping with a known set of keys: unknown and duplicate keys are
// refused on construction; getters convert, range-check and name the key.
class MapReader {
 public:
  MapReader(const std::string& file, const YAML::Node& node, std::string path, std::vector<std::string> allowed)
      : file_(file), node_(node), path_(std::move(path)), allowed_(std::move(allowed)) {
    if (!node_.IsMap()) fail_at(node_, path_, "expected a mapping of keys");
    std::set<std::string> seen;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      if (!it->first.IsScalar()) fail_at(it->first, path_, "a key must be a plain name");
      const std::string key = it->first.Scalar();
      if (!seen.insert(key).second) {
        throw InputError(file_, full(key), show(it->second), "key appears twice", line_of(it->first));
      }
      if (std::find(allowed_.begin(), allowed_.end(), key) == allowed_.end()) {
        throw InputError(file_, full(key), show(it->second), suggestion(key, allowed_), line_of(it->first));
      }
    }
  }

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  int line() const { return line_of(node_); }
  std::string full(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }

  bool has(const std::string& key) const {
    const YAML::Node n = node_[key];
    return n.IsDefined();
  }
  YAML::Node node(const std::string& key) const { return node_[key]; }

  [[noreturn]] void fail_at(const YAML::Node& n, const std::string& key, const std::string& reason) const {
    throw InputError(file_, key, show(n), reason, line_of(n));
  }
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const {
    if (has(key)) fail_at(node(key), full(key), reason);
    throw InputError(file_, full(key), "", reason, line());
  }
  [[noreturn]] void missing(const std::string& key, const std::string& what) const {
    throw InputError(file_, full(key), "", "required key missing: " + what, line());
  }
  void require(bool ok, const std::string& key, const std::string& reason) const {
    if (!ok) fail(key, reason);
  }

  double number(const std::string& key, double fallback) const { return has(key) ? number(key) : fallback; }
  double number(const std::string& key) const {
    if (!has(key)) missing(key, "a number");
    return to_number(node(key), full(key));
  }
  double to_number(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar()) fail_at(n, key, "expected a number");
    double value = 0.0;
    if (!YAML::convert<double>::decode(n, value)) fail_at(n, key, "expected a number");
    if (!std::isfinite(value)) fail_at(n, key, "expected a finite number");
    return value;
  }

  long long integer(const std::string& key, long long fallback) const { return has(key) ? integer(key) : fallback; }
  long long integer(const std::string& key) const {
    if (!has(key)) missing(key, "an integer");
    return to_integer(node(key), full(key));
  }
  long long to_integer(const YAML::Node& n, const std::string& key) const {
    long long value = 0;
    if (!n.IsScalar() || !YAML::convert<long long>::decode(n, value)) fail_at(n, key, "expected an integer");
    return value;
  }

  bool boolean(const std::string& key, bool fallback) const {
    if (!has(key)) return fallback;
    bool value = false;
    const YAML::Node n = node(key);
    if (!n.IsScalar() || !YAML::convert<bool>::decode(n, value)) fail_at(n, full(key), "expected true or false");
    return value;
  }

  std::string text(const std::string& key, const std::string& fallback) const { return has(key) ? text(key) : fallback; }
  std::string text(const std::string& key) const {
    if (!has(key)) missing(key, "a string");
    const YAML::Node n = node(key);
    if (!n.IsScalar()) fail_at(n, full(key), "expected a string");
    return n.Scalar();
  }

  // A registered term's row by its word: the table is the list of words
  // (coupling_terms/), and the fallback's row is the default.
  template <class Row>
  const Row& term(const std::string& key, std::span<const Row> rows, const Row& fallback) const {
    if (!has(key)) return fallback;
    const YAML::Node n = node(key);
    if (n.IsScalar())
      if (const Row* row = find_named_row(rows, n.Scalar())) return *row;
    fail_at(n, full(key), "expected one of: " + row_names(rows));
  }

  template <class Enum>
  Enum choice(const std::string& key, std::initializer_list<std::pair<const char*, Enum>> table, Enum fallback) const {
    if (!has(key)) return fallback;
    return to_choice(node(key), full(key), table);
  }
  template <class Enum>
  Enum to_choice(const YAML::Node& n, const std::string& key,
                 std::initializer_list<std::pair<const char*, Enum>> table) const {
    std::string names;
    for (const auto& [name, value] : table) names += (names.empty() ? "" : ", ") + std::string(name);
    // YAML reads a bare `off` as a boolean; the scalar text is still "off".
    if (n.IsScalar()) {
      for (const auto& [name, value] : table) {
        if (n.Scalar() == name) return value;
      }
    }
    fail_at(n, key, "expected one of: " + names);
  }

  std::vector<double> numbers(const YAML::Node& n, const std::string& key, std::size_t count) const {
    if (!n.IsSequence() || n.size() != count) fail_at(n, key, fmt::format("expected a list of {} numbers", count));
    std::vector<double> out;
    for (std::size_t i = 0; i < count; ++i) out.push_back(to_number(n[i], key));
    return out;
  }
  Vec3 vec3(const std::string& key) const {
    if (!has(key)) missing(key, "a list [x, y, z]");
    const auto v = numbers(node(key), full(key), 3);
    return Vec3(v[0], v[1], v[2]);
  }
  Vec3 vec3(const std::string& key, const Vec3& fallback) const { return has(key) ? vec3(key) : fallback; }

 private:
  std::string file_;
  YAML::Node node_;
  std::string path_;
  std::vector<std::string> allowed_;
};

std::string num(double v) { return fmt::format("{}", v); }
std::string vec(const Vec3& v) { return fmt::format("[{}, {}, {}]", v.x(), v.y(), v.z()); }

// ---------------------------------------------------------------- sections

Box read_box(const MapReader& parent, const std::string& key) {
  if (!parent.has(key)) parent.missing(key, "a box {lower: [x,y,z], upper: [x,y,z]}");
  const MapReader m(parent.file(), parent.node(key), parent.full(key), {"lower", "upper"});
  Box box{m.vec3("lower"), m.vec3("upper")};
  for (int a = 0; a < 3; ++a) {
    if (!(box.upper[a] > box.lower[a])) {
      m.fail("upper", fmt::format("empty box: upper must exceed lower ({}) on every axis", vec(box.lower)));
    }
  }
  return box;
}

void read_mesh(const MapReader& root, Scene& scene) {
  if (!root.has("mesh")) {
    if (scene.effects.fluid) root.missing("mesh", "the fluid mesh {cells: [nx, ny, nz]} or {cell_size: h}");
    return;
  }
  const MapReader m(root.file(), root.node("mesh"), "mesh", {"cells", "cell_size"});
  if (m.has("cells") == m.has("cell_size")) m.fail("cells", "give exactly one of mesh.cells or mesh.cell_size");
  const Vec3 length = scene.domain.upper - scene.domain.lower;
  if (m.has("cells")) {
    const YAML::Node n = m.node("cells");
    if (!n.IsSequence() || n.size() != 3) m.fail_at(n, "mesh.cells", "expected a list of 3 integers");
    for (std::size_t a = 0; a < 3; ++a) {
      const long long c = m.to_integer(n[a], "mesh.cells");
      if (c < 1) m.fail_at(n[a], "mesh.cells", "every cell count must be >= 1");
      if (c > 100000) m.fail_at(n[a], "mesh.cells", "cell count above 100000 per direction");
      scene.cells[a] = static_cast<int>(c);
    }
  } else {
    const YAML::Node n = m.node("cell_size");
    Vec3 h;
    if (n.IsSequence()) {
      const auto v = m.numbers(n, "mesh.cell_size", 3);
      h = Vec3(v[0], v[1], v[2]);
    } else {
      h = Vec3::Constant(m.to_number(n, "mesh.cell_size"));
    }
    for (int a = 0; a < 3; ++a) {
      if (!(h[a] > 0.0)) m.fail_at(n, "mesh.cell_size", "cell size must be > 0");
      const double ratio = length[a] / h[a];
      if (ratio > 100000.0) m.fail_at(n, "mesh.cell_size", "more than 100000 cells per direction");
      const double whole = std::round(ratio);
      // The box must hold a whole number of cells; 1e-6 absorbs decimal round-off like 0.044/0.004.
      if (whole < 1.0 || std::abs(ratio - whole) > 1e-6 * whole) {
        m.fail_at(n, "mesh.cell_size",
                  fmt::format("domain length {} m on axis {} is not a whole number of cells ({})", length[a], "xyz"[a],
                              ratio));
      }
      scene.cells[static_cast<std::size_t>(a)] = static_cast<int>(whole);
    }
  }
  // Elements are numbered with 32-bit Index: 5 * cells must fit.
  const double elements = 5.0 * scene.cells[0] * scene.cells[1] * scene.cells[2];
  if (elements > static_cast<double>(std::numeric_limits<Index>::max())) {
    m.fail(m.has("cells") ? "cells" : "cell_size", fmt::format("{} elements exceed the 32-bit index range", elements));
  }
}

void read_effects(const MapReader& root, Scene& scene) {
  Effects& e = scene.effects;
  if (!root.has("effects")) return;
  const MapReader m(root.file(), root.node("effects"), "effects",
                    {"fluid", "coupling", "gravity", "buoyancy", "drag", "normal_contact", "tangential_contact",
                     "rotation", "walls"});
  e.fluid = m.boolean("fluid", true);
  // Without a fluid there is nothing to couple to and nothing to float in.
  e.coupling = m.choice<CouplingMode>("coupling",
                                      {{"off", CouplingMode::off},
                                       {"fluid_to_particle", CouplingMode::fluid_to_particle},
                                       {"particle_to_fluid", CouplingMode::particle_to_fluid},
                                       {"two_way", CouplingMode::two_way}},
                                      e.fluid ? CouplingMode::two_way : CouplingMode::off);
  e.buoyancy = m.boolean("buoyancy", e.fluid);
  if (!e.fluid && e.coupling != CouplingMode::off) m.fail("coupling", "coupling needs effects.fluid: true");
  if (!e.fluid && e.buoyancy) m.fail("buoyancy", "buoyancy needs effects.fluid: true");
  e.gravity = m.boolean("gravity", true);
  e.drag = m.text("drag", e.drag);
  if (find_drag_law(e.drag) == nullptr) m.fail("drag", "expected one of: " + drag_law_names());
  e.normal_contact = m.boolean("normal_contact", true);
  e.tangential_contact = m.boolean("tangential_contact", false);
  if (e.tangential_contact && !e.normal_contact) {
    m.fail("tangential_contact", "tangential contact needs normal_contact: true (Coulomb cap uses the normal force)");
  }
  e.rotation = m.boolean("rotation", false);
  e.walls = m.boolean("walls", true);
}

FaceBoundary read_face(const MapReader& b, const std::string& face) {
  FaceBoundary f;
  const YAML::Node n = b.node(face);
  const std::string key = b.full(face);
  const std::initializer_list<std::pair<const char*, FaceCondition>> table{{"no_slip", FaceCondition::no_slip},
                                                                            {"free_slip", FaceCondition::free_slip},
                                                                            {"inlet", FaceCondition::inlet},
                                                                            {"outlet", FaceCondition::outlet}};
  if (n.IsScalar()) {
    f.condition = b.to_choice<FaceCondition>(n, key, table);
    if (f.condition == FaceCondition::inlet) b.fail_at(n, key, "an inlet needs {type: inlet, velocity: [u, v, w]}");
    return f;
  }
  const MapReader m(b.file(), n, key, {"type", "velocity", "above", "superficial"});
  if (!m.has("type")) m.missing("type", "no_slip, free_slip, inlet or outlet");
  f.condition = m.to_choice<FaceCondition>(m.node("type"), m.full("type"), table);
  if (f.condition == FaceCondition::inlet) {
    f.velocity = m.vec3("velocity");
    f.inlet_above_m = m.number("above", f.inlet_above_m);
    f.superficial = m.boolean("superficial", false);
  } else {
    if (m.has("superficial")) m.fail("superficial", "superficial applies to an inlet only");
    if (m.has("velocity")) m.fail("velocity", "velocity applies to an inlet only");
    if (m.has("above")) m.fail("above", "above applies to an inlet only");
  }
  return f;
}

void read_fluid(const MapReader& root, Scene& scene) {
  if (!root.has("fluid")) {
    if (scene.effects.fluid) root.missing("fluid", "fluid properties {density, viscosity}");
    return;
  }
  FluidSpec& f = scene.fluid;
  const MapReader m(root.file(), root.node("fluid"), "fluid", {"density", "viscosity", "time_scheme", "scheme", "boundaries", "solver",
                                                               "model", "porosity_time_derivative"});
  f.density = m.number("density");
  m.require(f.density > 0.0, "density", "fluid density must be > 0 [kg/m^3]");
  f.viscosity = m.number("viscosity");
  m.require(f.viscosity > 0.0, "viscosity", "dynamic viscosity must be > 0 [Pa s]");
  f.time_scheme = m.choice<TimeScheme>("time_scheme", {{"bdf1", TimeScheme::bdf1}, {"bdf2", TimeScheme::bdf2}},
                                       TimeScheme::bdf2);
  f.scheme = m.choice<FluidScheme>("scheme", {{"monolithic", FluidScheme::monolithic}, {"projection", FluidScheme::projection}},
                                   FluidScheme::monolithic);
  f.model = m.choice<FluidModel>(
      "model", {{"simplified", FluidModel::simplified}, {"vans_a", FluidModel::vans_a}, {"vans_b", FluidModel::vans_b}},
      FluidModel::simplified);
  f.porosity_time_derivative = m.boolean("porosity_time_derivative", false);
  m.require(!f.porosity_time_derivative || f.model != FluidModel::simplified, "porosity_time_derivative",
            "applies to the volume-averaged models only (fluid.model: vans_a or vans_b)");
  if (m.has("boundaries")) {
    static const std::vector<std::string> faces{"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    const MapReader b(m.file(), m.node("boundaries"), "fluid.boundaries", faces);
    for (std::size_t i = 0; i < faces.size(); ++i) {
      if (b.has(faces[i])) f.faces[i] = read_face(b, faces[i]);
    }
  }
  if (m.has("solver")) {
    const MapReader s(m.file(), m.node("solver"), "fluid.solver",
                      {"linear_tolerance", "max_linear_iterations", "picard_tolerance", "max_picard_iterations",
                       "linearization", "linear_solver", "petsc_options"});
    f.linear_solver = s.choice<FluidLinearSolverChoice>(
        "linear_solver",
        {{"eigen_bicgstab_ilut", FluidLinearSolverChoice::eigen_bicgstab_ilut},
         {"petsc", FluidLinearSolverChoice::petsc}},
        f.linear_solver);
    if (s.has("petsc_options")) {
      f.petsc_options = s.text("petsc_options");
      s.require(f.linear_solver == FluidLinearSolverChoice::petsc, "petsc_options",
                "needs fluid.solver.linear_solver: petsc");
      const auto first = f.petsc_options.find_first_not_of(" \t");
      s.require(first == std::string::npos || f.petsc_options[first] == '-', "petsc_options",
                "must be PETSc options, e.g. \"-pc_type fieldsplit\"");
    }
    f.linearization = s.choice<FluidLinearization>(
        "linearization",
        {{"picard", FluidLinearization::picard}, {"extrapolated", FluidLinearization::extrapolated}},
        f.linearization);
    f.linear_tolerance = s.number("linear_tolerance", f.linear_tolerance);
    s.require(f.linear_tolerance > 0.0 && f.linear_tolerance < 1.0, "linear_tolerance", "must lie in (0, 1)");
    f.picard_tolerance = s.number("picard_tolerance", f.picard_tolerance);
    s.require(f.picard_tolerance > 0.0 && f.picard_tolerance < 1.0, "picard_tolerance", "must lie in (0, 1)");
    const long long linear = s.integer("max_linear_iterations", f.max_linear_iterations);
    s.require(linear >= 1 && linear <= 10000000, "max_linear_iterations", "must lie in [1, 1e7]");
    f.max_linear_iterations = static_cast<int>(linear);
    const long long picard = s.integer("max_picard_iterations", f.max_picard_iterations);
    s.require(picard >= 1 && picard <= 10000, "max_picard_iterations", "must lie in [1, 10000]");
    f.max_picard_iterations = static_cast<int>(picard);
  }
  if (f.scheme == FluidScheme::projection) {
    // What fluid/projection_scheme.hpp does not do; refused before any step.
    m.require(f.model == FluidModel::simplified, "scheme",
              "projection solves the simplified model only (fluid.model: simplified); use scheme: monolithic");
    m.require(f.linearization == FluidLinearization::extrapolated, "scheme",
              "projection advects with the extrapolated velocity; fluid.solver.linearization: picard needs scheme: "
              "monolithic");
    m.require(f.linear_solver != FluidLinearSolverChoice::petsc, "scheme",
              "projection solves with its own Eigen solvers; fluid.solver.linear_solver: petsc (and petsc_options) "
              "need scheme: monolithic");
  }
}

SizeDistribution read_size(const MapReader& set) {
  SizeDistribution s;
  const YAML::Node n = set.node("size");
  if (n.IsScalar()) {  // shorthand: size: 7.6e-4 is a fixed diameter
    s.kind = SizeKind::fixed;
    s.diameter = set.to_number(n, set.full("size"));
    if (!(s.diameter > 0.0)) set.fail_at(n, set.full("size"), "diameter must be > 0 [m]");
    return s;
  }
  const MapReader m(set.file(), n, set.full("size"), {"distribution", "diameter", "min", "max", "mean", "sd"});
  s.kind = m.choice<SizeKind>("distribution",
                              {{"fixed", SizeKind::fixed}, {"uniform", SizeKind::uniform}, {"normal", SizeKind::normal}},
                              SizeKind::fixed);
  auto only = [&](std::initializer_list<const char*> keys, const char* kind) {
    for (const char* k : {"diameter", "min", "max", "mean", "sd"}) {
      if (m.has(k) && std::find_if(keys.begin(), keys.end(), [&](const char* a) { return std::string_view(a) == k; }) ==
                          keys.end()) {
        m.fail(k, fmt::format("does not apply to a {} distribution", kind));
      }
    }
  };
  switch (s.kind) {
    case SizeKind::fixed:
      only({"diameter"}, "fixed");
      s.diameter = m.number("diameter");
      m.require(s.diameter > 0.0, "diameter", "diameter must be > 0 [m]");
      break;
    case SizeKind::uniform:
      only({"min", "max"}, "uniform");
      s.minimum = m.number("min");
      s.maximum = m.number("max");
      m.require(s.minimum > 0.0, "min", "smallest diameter must be > 0 [m]");
      m.require(s.maximum >= s.minimum, "max", fmt::format("must be >= min ({})", s.minimum));
      break;
    case SizeKind::normal:
      only({"mean", "sd", "min", "max"}, "normal");
      s.mean = m.number("mean");
      s.sd = m.number("sd");
      if (!m.has("min")) m.missing("min", "the lower truncation bound (> 0) of the normal distribution");
      if (!m.has("max")) m.missing("max", "the upper truncation bound of the normal distribution");
      s.minimum = m.number("min");
      s.maximum = m.number("max");
      m.require(s.mean > 0.0, "mean", "mean diameter must be > 0 [m]");
      m.require(s.sd > 0.0, "sd", "standard deviation must be > 0 [m] (use distribution: fixed otherwise)");
      m.require(s.minimum > 0.0, "min",
                "truncation bound must be > 0: otherwise the normal distribution can draw diameters <= 0");
      m.require(s.maximum > s.minimum, "max", fmt::format("must exceed min ({})", s.minimum));
      {
        // Rejection sampling draws until d lies in [min, max]: refuse bounds that
        // would rarely be hit: below 1e-3 acceptance a draw costs over 1000 tries, and a
        // large set would stall before the run starts.
        const double acceptance =
            gsl_cdf_gaussian_P(s.maximum - s.mean, s.sd) - gsl_cdf_gaussian_P(s.minimum - s.mean, s.sd);
        if (!(acceptance >= 1e-3)) {
          m.fail("min", fmt::format("[min, max] holds a fraction {:.3g} of the normal distribution (below 1e-3): truncation by "
                                    "rejection would stall",
                                    acceptance));
        }
      }
      break;
  }
  return s;
}

bool box_inside(const Box& inner, const Box& outer) {
  return (inner.lower.array() >= outer.lower.array()).all() && (inner.upper.array() <= outer.upper.array()).all();
}

void read_particle_set(const MapReader& list_item, const std::string& base_dir, Scene& scene, std::size_t index) {
  const MapReader& m = list_item;
  ParticleSet p;
  p.name = m.text("name", fmt::format("set{}", index));
  if (!m.has("placement")) m.missing("placement", "single, lattice, random or csv");
  p.placement = m.choice<PlacementKind>("placement",
                                        {{"single", PlacementKind::single},
                                         {"lattice", PlacementKind::lattice},
                                         {"random", PlacementKind::random},
                                         {"csv", PlacementKind::csv}},
                                        PlacementKind::single);
  // Keys that belong to another placement are mistakes, not silent no-ops.
  const std::vector<std::pair<std::string, PlacementKind>> owned{
      {"position", PlacementKind::single}, {"lattice", PlacementKind::lattice}, {"count", PlacementKind::random},
      {"file", PlacementKind::csv}};
  for (const auto& [key, owner] : owned) {
    if (m.has(key) && owner != p.placement) m.fail(key, "does not apply to this placement");
  }
  if (p.placement == PlacementKind::single || p.placement == PlacementKind::csv) {
    if (m.has("region")) m.fail("region", "does not apply to this placement");
  }
  if (p.placement == PlacementKind::csv) {
    for (const char* k : {"size", "density"}) {
      if (m.has(k)) m.fail(k, "a csv file gives each particle's d and rho");
    }
  }

  if (p.placement != PlacementKind::csv) {
    if (!m.has("size")) m.missing("size", "a diameter or {distribution: fixed|uniform|normal, ...}");
    p.size = read_size(m);
    p.density = m.number("density");
    m.require(p.density > 0.0, "density", "particle density must be > 0 [kg/m^3]");
  }
  p.velocity = m.vec3("velocity", p.velocity);
  const long long seed = m.integer("seed", 1);
  m.require(seed >= 0, "seed", "seed must be >= 0");
  p.seed = static_cast<std::uint64_t>(seed);

  const double d_max = p.placement == PlacementKind::csv ? 0.0 : largest_diameter(p.size);
  switch (p.placement) {
    case PlacementKind::single: {
      p.position = m.vec3("position");
      const Box sphere{p.position - Vec3::Constant(0.5 * d_max), p.position + Vec3::Constant(0.5 * d_max)};
      if (!box_inside(sphere, scene.domain)) {
        m.fail("position", fmt::format("the particle (d = {} m) does not lie inside the domain {} .. {}", d_max,
                                       vec(scene.domain.lower), vec(scene.domain.upper)));
      }
      break;
    }
    case PlacementKind::lattice:
    case PlacementKind::random: {
      p.region = read_box(m, "region");
      if (!box_inside(p.region, scene.domain)) {
        m.fail("region", fmt::format("region lies outside the domain {} .. {}", vec(scene.domain.lower),
                                     vec(scene.domain.upper)));
      }
      const Vec3 extent = p.region.upper - p.region.lower;
      if (p.placement == PlacementKind::lattice) {
        const YAML::Node n = m.node("lattice");
        if (!n.IsDefined()) m.missing("lattice", "site counts [nx, ny, nz]");
        if (!n.IsSequence() || n.size() != 3) m.fail_at(n, m.full("lattice"), "expected a list of 3 integers");
        double sites = 1.0;
        for (std::size_t a = 0; a < 3; ++a) {
          const long long c = m.to_integer(n[a], m.full("lattice"));
          if (c < 1) m.fail_at(n[a], m.full("lattice"), "every site count must be >= 1");
          if (c > 1000000) m.fail_at(n[a], m.full("lattice"), "site count above 1e6 per direction");
          p.lattice[a] = static_cast<int>(c);
          sites *= static_cast<double>(c);
          // Sites sit at the centres of n equal sub-boxes: spacing = extent / n.
          const double spacing = extent[static_cast<Eigen::Index>(a)] / static_cast<double>(c);
          if (spacing < d_max) {
            m.fail_at(n[a], m.full("lattice"),
                      fmt::format("lattice spacing {} m on axis {} is below the largest diameter {} m: particles "
                                  "would overlap",
                                  spacing, "xyz"[a], d_max));
          }
        }
        if (sites > 1e8) m.fail("lattice", fmt::format("{} particles: above the 1e8 limit", sites));
      } else {
        const long long count = m.integer("count");
        m.require(count >= 1 && count <= 100000000, "count", "count must lie in [1, 1e8]");
        p.count = static_cast<int>(count);
        for (int a = 0; a < 3; ++a) {
          if (extent[a] < d_max) m.fail("region", fmt::format("region is narrower than the largest diameter {} m", d_max));
        }
        // Spheres occupy at most ~64 % of a box when packed at random (random close
        // packing); ask for at most half, or placement would not end.
        const double solid = static_cast<double>(count) * sphere_volume(d_max);
        if (solid > 0.5 * extent.prod()) {
          m.fail("count", fmt::format("{} particles of up to {} m fill more than half the region: random placement "
                                      "would not find room",
                                      count, d_max));
        }
      }
      break;
    }
    case PlacementKind::csv: {
      const std::string file = m.text("file");
      std::filesystem::path path(file);
      if (path.is_relative()) path = std::filesystem::path(base_dir) / path;
      p.csv_file = path.lexically_normal().string();
      const auto records = read_particle_csv(p.csv_file);
      for (const auto& r : records) {
        const Box sphere{r.position - Vec3::Constant(0.5 * r.diameter), r.position + Vec3::Constant(0.5 * r.diameter)};
        if (!box_inside(sphere, scene.domain)) {
          throw InputError(p.csv_file, "x,y,z", vec(r.position),
                           fmt::format("particle (d = {} m) lies outside the domain {} .. {}", r.diameter,
                                       vec(scene.domain.lower), vec(scene.domain.upper)),
                           r.line);
        }
      }
      if (records.empty()) m.fail("file", "the csv file holds no particles");
      break;
    }
  }
  scene.particles.push_back(std::move(p));
}

void read_particles(const MapReader& root, const std::string& base_dir, Scene& scene) {
  if (!root.has("particles")) return;
  const YAML::Node list = root.node("particles");
  if (!list.IsSequence()) root.fail("particles", "expected a list of particle sets (- name: ...)");
  std::set<std::string> names;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string path = fmt::format("particles[{}]", i);
    const MapReader m(root.file(), list[i], path,
                      {"name", "placement", "position", "region", "lattice", "count", "file", "size", "density",
                       "velocity", "seed"});
    read_particle_set(m, base_dir, scene, i);
    if (!names.insert(scene.particles.back().name).second) m.fail("name", "two particle sets share this name");
  }
}

void read_contact(const MapReader& root, Scene& scene) {
  ContactSpec& c = scene.contact;
  const bool needed = !scene.particles.empty() && scene.effects.normal_contact;
  if (!root.has("contact")) {
    if (needed)
      root.missing("contact", fmt::format("contact parameters {} ({}, the default law)",
                                          contact_law_entry(c.law).keys, contact_law_entry(c.law).name));
    return;
  }
  const MapReader m(root.file(), root.node("contact"), "contact",
                    {"law", "kn", "cn", "restitution", "kt", "ct", "friction", "allow_unstable_step"});
  c.law = m.term("law", contact_laws(), contact_law_entry(c.law)).code;
  c.normal_stiffness = needed ? m.number("kn") : m.number("kn", 0.0);
  if (needed) m.require(c.normal_stiffness > 0.0, "kn", "normal stiffness must be > 0 [N/m]");
  else m.require(c.normal_stiffness >= 0.0, "kn", "normal stiffness must be >= 0 [N/m]");
  if (m.has("cn") && m.has("restitution")) m.fail("restitution", "give cn or restitution, not both");
  c.normal_damping = m.number("cn", 0.0);
  m.require(c.normal_damping >= 0.0, "cn", "normal damping must be >= 0 [N s/m]");
  if (m.has("restitution")) {
    const double e = m.number("restitution");
    m.require(e > 0.0 && e <= 1.0, "restitution", "coefficient of restitution must lie in (0, 1]");
    c.restitution = e;
  }
  c.tangential_stiffness = m.number("kt", 0.0);
  m.require(c.tangential_stiffness >= 0.0, "kt", "tangential stiffness must be >= 0 [N/m]");
  if (scene.effects.tangential_contact && !scene.particles.empty()) {
    m.require(c.tangential_stiffness > 0.0, "kt", "effects.tangential_contact needs kt > 0 [N/m]");
  }
  c.tangential_damping = m.number("ct", 0.0);
  m.require(c.tangential_damping >= 0.0, "ct", "tangential damping must be >= 0 [N s/m]");
  c.friction = m.number("friction", 0.0);
  m.require(c.friction >= 0.0, "friction", "friction coefficient must be >= 0");
  c.allow_unstable_step = m.boolean("allow_unstable_step", false);
}

void read_time(const MapReader& root, Scene& scene) {
  TimeSpec& t = scene.time;
  if (!root.has("time")) root.missing("time", "{fluid_step, dem_step, end}");
  const MapReader m(root.file(), root.node("time"), "time", {"fluid_step", "dem_step", "end", "subcycles"});
  // Which keys a file gives; the rules between the steps are
  // scene/time_steps.hpp's. A step given must be > 0 (in TimeSpec, 0 is
  // "not given"). A dry scene's fluid_step is its driver step.
  const bool has_particles = !scene.particles.empty();
  if (has_particles) {
    t.dem_step = m.number("dem_step");
    m.require(t.dem_step > 0.0, "dem_step", "time step must be > 0 [s]");
  } else if (m.has("dem_step")) {
    m.fail("dem_step", "the scene has no particles");
  }
  const long long subcycles = m.integer("subcycles", 0);
  m.require(subcycles >= 0 && subcycles <= 100000000, "subcycles", "must lie in [1, 1e8] (0 or absent: derived)");
  t.subcycles = static_cast<int>(subcycles);
  if (scene.effects.fluid || m.has("fluid_step")) {
    t.fluid_step = m.number("fluid_step");
    m.require(t.fluid_step > 0.0, "fluid_step", "time step must be > 0 [s]");
  }
  if (!has_particles && subcycles > 0) m.fail("subcycles", "the scene has no particles");
  t = resolve_time_steps(scene, std::nullopt, [&m](const std::string& key, const std::string& reason) {
    m.fail(key, reason);
  });
  t.end_time = m.number("end");
  m.require(t.end_time >= t.fluid_step, "end", fmt::format("end time is below one time step ({} s)", t.fluid_step));
  if (t.end_time / t.fluid_step > 1e9) m.fail("end", "more than 1e9 time steps");
}

void read_coupling(const MapReader& root, Scene& scene) {
  CouplingSpec& c = scene.coupling;
  // The momentum exchange's default: semi-implicit with a volume-averaged
  // fluid (the dense regime it is for), explicit with the paper's simplified
  // model (its studies unchanged).
  if (scene.fluid.model != FluidModel::simplified) c.exchange = MomentumExchange::semi_implicit;
  // The volume-averaged models couple the fluid to exactly minus the grains'
  // force (coupling/source_term.hpp); Eq. 22's F/eps is the simplified model's.
  if (scene.fluid.model != FluidModel::simplified) c.source_form = SourceForm::conservative;
  if (!root.has("coupling")) return;
  const MapReader m(root.file(), root.node("coupling"), "coupling",
                    {"porosity", "porosity_floor", "porosity_smoothing_length", "porosity_smoothing_diameters",
                     "source_form", "exchange", "freeze_until"});
  c.porosity = m.term("porosity", porosity_schemes(), porosity_scheme_entry(c.porosity)).code;
  c.porosity_floor = m.number("porosity_floor", c.porosity_floor);
  m.require(c.porosity_floor > 0.0 && c.porosity_floor < 1.0, "porosity_floor", "must lie in (0, 1)");
  if (m.has("porosity_smoothing_length")) {
    c.porosity_smoothing_length = m.number("porosity_smoothing_length");
    m.require(*c.porosity_smoothing_length > 0.0, "porosity_smoothing_length", "must be > 0 [m]");
  }
  if (m.has("porosity_smoothing_diameters")) {
    c.porosity_smoothing_diameters = m.number("porosity_smoothing_diameters");
    m.require(*c.porosity_smoothing_diameters > 0.0, "porosity_smoothing_diameters", "must be > 0");
    m.require(!c.porosity_smoothing_length, "porosity_smoothing_diameters",
              "give the smoothing length in diameters or in metres (porosity_smoothing_length), not both");
  }
  c.source_form = m.term("source_form", source_forms(), source_form_entry(c.source_form)).code;
  m.require(c.source_form == SourceForm::conservative || scene.fluid.model == FluidModel::simplified, "source_form",
            "paper (Eq. 22, F/eps) is the simplified model's; fluid.model vans_a / vans_b take exactly minus the "
            "grains' force (conservative)");
  c.exchange = m.term("exchange", momentum_exchanges(), momentum_exchange_entry(c.exchange)).code;
  c.freeze_until = m.number("freeze_until", c.freeze_until);
  m.require(c.freeze_until >= 0.0, "freeze_until", "must be >= 0 [s]");
}

void read_output(const MapReader& root, Scene& scene) {
  if (!root.has("output")) return;
  OutputSpec& o = scene.output;
  const MapReader m(root.file(), root.node("output"), "output",
                    {"directory", "vtu_interval", "vtu_format", "csv_interval", "checkpoint_interval", "probes"});
  o.directory = m.text("directory", o.directory);
  o.vtu_format =
      m.choice<VtuFormat>("vtu_format", {{"binary", VtuFormat::binary}, {"ascii", VtuFormat::ascii}}, o.vtu_format);
  m.require(!o.directory.empty(), "directory", "must not be empty");
  for (const char* key : {"vtu_interval", "csv_interval", "checkpoint_interval"}) {
    const double v = m.number(key, 0.0);
    m.require(v >= 0.0, key, "must be >= 0 [s] (0: see examples/README.md)");
    if (std::string_view(key) == "vtu_interval") o.vtu_interval = v;
    else if (std::string_view(key) == "csv_interval") o.csv_interval = v;
    else o.checkpoint_interval = v;
  }
  if (m.has("probes")) {
    const YAML::Node n = m.node("probes");
    if (!n.IsSequence()) m.fail("probes", "expected a list of probe names");
    std::vector<std::string> valid;
    for (auto name : probe_names()) valid.emplace_back(name);
    for (std::size_t i = 0; i < n.size(); ++i) {
      if (!n[i].IsScalar()) m.fail_at(n[i], "output.probes", "expected a probe name");
      const std::string name = n[i].Scalar();
      if (!is_probe_name(name)) {
        throw InputError(root.file(), "output.probes", name, suggestion(name, valid), line_of(n[i]));
      }
      o.probes.push_back(name);
    }
  }
}

Scene read_scene(const YAML::Node& doc, const std::string& file, const std::string& base_dir) {
  Scene scene;
  scene.source_file = file;
  if (!doc.IsDefined() || doc.IsNull()) throw InputError(file, "(document)", "", "the scene file is empty");
  const MapReader root(file, doc, "",
                       {"title", "domain", "mesh", "gravity", "effects", "fluid", "particles", "contact", "time",
                        "coupling", "output"});
  scene.title = root.text("title", "");
  read_effects(root, scene);
  scene.domain = read_box(root, "domain");
  read_mesh(root, scene);
  scene.gravity = root.vec3("gravity", scene.gravity);
  read_fluid(root, scene);
  read_particles(root, base_dir, scene);
  if (!scene.effects.fluid && scene.particles.empty()) {
    root.fail("particles", "nothing to simulate: no fluid (effects.fluid: false) and no particles");
  }
  read_contact(root, scene);
  read_time(root, scene);
  read_coupling(root, scene);
  read_output(root, scene);
  if (scene.coupling.freeze_until > scene.time.end_time) {
    throw InputError(file, "coupling.freeze_until", num(scene.coupling.freeze_until),
                     fmt::format("beyond the end time {} s", scene.time.end_time));
  }
  return scene;
}

template <class Load>
Scene parse_guarded(const std::string& file, const std::string& base_dir, Load&& load) {
  try {
    return read_scene(load(), file, base_dir);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, "(syntax)", "", "not valid YAML: " + e.msg, e.mark.line >= 0 ? e.mark.line + 1 : 0);
  } catch (const YAML::BadFile&) {
    throw InputError(file, "(file)", file, "cannot open the scene file");
  } catch (const YAML::Exception& e) {
    throw InputError(file, "(document)", "", "cannot read the scene: " + e.msg,
                     e.mark.line >= 0 ? e.mark.line + 1 : 0);
  }
}

}  // namespace

double largest_diameter(const SizeDistribution& size) {
  return size.kind == SizeKind::fixed ? size.diameter : size.maximum;
}
double smallest_diameter(const SizeDistribution& size) {
  return size.kind == SizeKind::fixed ? size.diameter : size.minimum;
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(path, "(file)", path, "is a directory, not a scene file: give the scene's .yaml file");
  }
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path, "(file)", path, "no such scene file");
  }
  const std::string base_dir = std::filesystem::path(path).parent_path().string();
  return parse_guarded(path, base_dir.empty() ? "." : base_dir, [&] { return YAML::LoadFile(path); });
}

Scene load_scene_from_string(const std::string& text, const std::string& file_name, const std::string& base_dir) {
  return parse_guarded(file_name, base_dir, [&] { return YAML::Load(text); });
}

}  // namespace fdem

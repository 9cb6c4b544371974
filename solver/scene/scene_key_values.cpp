#include "scene/scene_key_values.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "drag_laws/drag_law.hpp"
#include "scene/scene_schema.hpp"

namespace fdem {

namespace {

// Appends one key's values under its name.
class Values {
 public:
  Values(SceneKeyValues& out, std::string name) : out_(out), name_(std::move(name)) {}
  void number(double v) { out_.emplace_back(name_, v); }
  void flag(bool b) { number(b ? 1.0 : 0.0); }
  template <class Enum>
  void choice(Enum e) {
    number(static_cast<double>(e));
  }
  // A string's value: 53 bits of its FNV-1a hash, exact in a double (equal
  // strings, equal values; any change of the text changes it).
  void text(std::string_view t) {
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const char c : t) {
      h ^= static_cast<unsigned char>(c);
      h *= 0x100000001b3ULL;
    }
    number(static_cast<double>(h >> 11));
  }
  void vec(const Vec3& v) {
    out_.emplace_back(name_ + ".x", v.x());
    out_.emplace_back(name_ + ".y", v.y());
    out_.emplace_back(name_ + ".z", v.z());
  }
  // A key under fluid.boundaries.<face>: one value per face, named by it.
  template <class Get>
  void per_face(std::string_view leaf, Get get) {
    static constexpr const char* kFaces[6] = {"x_min", "x_max", "y_min", "y_max", "z_min", "z_max"};
    for (std::size_t k = 0; k < 6; ++k) {
      Values face(out_, std::string("fluid.boundaries.") + kFaces[k] + "." + std::string(leaf));
      get(face, k);
    }
  }

 private:
  SceneKeyValues& out_;
  std::string name_;
};

struct KeyValue {
  std::string_view path;  // schema path
  void (*add)(const Scene&, Values&);
};

// One row per fingerprinted schema key (scene_schema.cpp; the exempt keys
// and why: fingerprint_exemption there).
constexpr KeyValue kKeyValues[] = {
    {"domain.lower", [](const Scene& s, Values& v) { v.vec(s.domain.lower); }},
    {"domain.upper", [](const Scene& s, Values& v) { v.vec(s.domain.upper); }},
    {"mesh.cells",
     [](const Scene& s, Values& v) {
       v.vec(Vec3(s.cells[0], s.cells[1], s.cells[2]));  // also what mesh.cell_size resolves to
     }},
    {"gravity", [](const Scene& s, Values& v) { v.vec(s.gravity); }},
    {"effects.fluid", [](const Scene& s, Values& v) { v.flag(s.effects.fluid); }},
    {"effects.coupling", [](const Scene& s, Values& v) { v.choice(s.effects.coupling); }},
    {"effects.gravity", [](const Scene& s, Values& v) { v.flag(s.effects.gravity); }},
    {"effects.buoyancy", [](const Scene& s, Values& v) { v.flag(s.effects.buoyancy); }},
    {"effects.drag",
     [](const Scene& s, Values& v) {
       v.number(static_cast<double>(drag_law_index(drag_law(s.effects.drag))));  // the law's row in the table
     }},
    {"effects.normal_contact", [](const Scene& s, Values& v) { v.flag(s.effects.normal_contact); }},
    {"effects.tangential_contact", [](const Scene& s, Values& v) { v.flag(s.effects.tangential_contact); }},
    {"effects.rotation", [](const Scene& s, Values& v) { v.flag(s.effects.rotation); }},
    {"effects.walls", [](const Scene& s, Values& v) { v.flag(s.effects.walls); }},
    {"fluid.density", [](const Scene& s, Values& v) { v.number(s.fluid.density); }},
    {"fluid.viscosity", [](const Scene& s, Values& v) { v.number(s.fluid.viscosity); }},
    {"fluid.time_scheme", [](const Scene& s, Values& v) { v.choice(s.fluid.time_scheme); }},
    {"fluid.scheme", [](const Scene& s, Values& v) { v.choice(s.fluid.scheme); }},
    {"fluid.model", [](const Scene& s, Values& v) { v.choice(s.fluid.model); }},
    {"fluid.porosity_time_derivative", [](const Scene& s, Values& v) { v.flag(s.fluid.porosity_time_derivative); }},
    {"fluid.boundaries.<face>.type",
     [](const Scene& s, Values& v) {
       v.per_face("type", [&s](Values& f, std::size_t k) { f.choice(s.fluid.faces[k].condition); });
     }},
    {"fluid.boundaries.<face>.velocity",
     [](const Scene& s, Values& v) {
       v.per_face("velocity", [&s](Values& f, std::size_t k) { f.vec(s.fluid.faces[k].velocity); });
     }},
    {"fluid.boundaries.<face>.above",
     [](const Scene& s, Values& v) {
       v.per_face("above", [&s](Values& f, std::size_t k) { f.number(s.fluid.faces[k].inlet_above_m); });
     }},
    {"fluid.boundaries.<face>.superficial",
     [](const Scene& s, Values& v) {
       v.per_face("superficial", [&s](Values& f, std::size_t k) { f.flag(s.fluid.faces[k].superficial); });
     }},
    {"fluid.solver.linear_tolerance", [](const Scene& s, Values& v) { v.number(s.fluid.linear_tolerance); }},
    {"fluid.solver.max_linear_iterations", [](const Scene& s, Values& v) { v.number(s.fluid.max_linear_iterations); }},
    {"fluid.solver.picard_tolerance", [](const Scene& s, Values& v) { v.number(s.fluid.picard_tolerance); }},
    {"fluid.solver.max_picard_iterations", [](const Scene& s, Values& v) { v.number(s.fluid.max_picard_iterations); }},
    {"fluid.solver.linearization", [](const Scene& s, Values& v) { v.choice(s.fluid.linearization); }},
    {"fluid.solver.linear_solver", [](const Scene& s, Values& v) { v.choice(s.fluid.linear_solver); }},
    {"fluid.solver.petsc_options", [](const Scene& s, Values& v) { v.text(s.fluid.petsc_options); }},
    {"contact.law", [](const Scene& s, Values& v) { v.choice(s.contact.law); }},
    {"contact.kn", [](const Scene& s, Values& v) { v.number(s.contact.normal_stiffness); }},
    {"contact.cn", [](const Scene& s, Values& v) { v.number(s.contact.normal_damping); }},
    {"contact.restitution", [](const Scene& s, Values& v) { v.number(s.contact.restitution.value_or(-1.0)); }},
    {"contact.kt", [](const Scene& s, Values& v) { v.number(s.contact.tangential_stiffness); }},
    {"contact.ct", [](const Scene& s, Values& v) { v.number(s.contact.tangential_damping); }},
    {"contact.friction", [](const Scene& s, Values& v) { v.number(s.contact.friction); }},
    {"time.fluid_step", [](const Scene& s, Values& v) { v.number(s.time.fluid_step); }},
    {"time.dem_step", [](const Scene& s, Values& v) { v.number(s.time.dem_step); }},
    {"time.subcycles", [](const Scene& s, Values& v) { v.number(s.time.subcycles); }},
    {"coupling.porosity", [](const Scene& s, Values& v) { v.choice(s.coupling.porosity); }},
    {"coupling.porosity_floor", [](const Scene& s, Values& v) { v.number(s.coupling.porosity_floor); }},
    {"coupling.porosity_smoothing_length",
     [](const Scene& s, Values& v) { v.number(s.coupling.porosity_smoothing_length.value_or(-1.0)); }},
    {"coupling.porosity_smoothing_diameters",
     [](const Scene& s, Values& v) { v.number(s.coupling.porosity_smoothing_diameters.value_or(-1.0)); }},
    {"coupling.source_form", [](const Scene& s, Values& v) { v.choice(s.coupling.source_form); }},
    {"coupling.exchange", [](const Scene& s, Values& v) { v.choice(s.coupling.exchange); }},
    {"coupling.freeze_until", [](const Scene& s, Values& v) { v.number(s.coupling.freeze_until); }},
};

}  // namespace

SceneKeyValues fingerprinted_values(const Scene& scene) {
  SceneKeyValues out;
  for (const SceneKey& key : scene_schema()) {
    if (key.is_map || fingerprint_exemption(key.path) != nullptr) continue;
    const auto* row = std::find_if(std::begin(kKeyValues), std::end(kKeyValues),
                                   [&key](const KeyValue& k) { return k.path == key.path; });
    if (row == std::end(kKeyValues))
      throw std::logic_error("scene key '" + std::string(key.path) +
                             "' changes a step's result but has no value for the checkpoint's scene fingerprint: add "
                             "it to solver/scene/scene_key_values.cpp, or exempt it in scene_schema.cpp with the reason");
    Values values(out, std::string(key.path));
    row->add(scene, values);
  }
  return out;
}

std::vector<std::string> keys_with_values() {
  std::vector<std::string> out;
  for (const KeyValue& k : kKeyValues) out.emplace_back(k.path);
  return out;
}

}  // namespace fdem

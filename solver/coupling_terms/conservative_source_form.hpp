#pragma once
// The conservative source form: b_e = -sum_i f_i / V_e, so the fluid
// receives exactly minus the drag on the grains (Newton's third law),
// whatever the porosity scheme or floor (coupling/source_term.hpp).
namespace fdem {

struct ConservativeSourceForm {
  static double drag_to_fluid_force(double, double, double) { return -1.0; }
  static double exchange_coefficient(double coefficient_per_volume, double) { return coefficient_per_volume; }
};

}  // namespace fdem

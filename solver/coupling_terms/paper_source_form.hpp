#pragma once
// The paper's source form (Eq. 20, 22): per-particle source
// F_fp,i = (1 - eps_e) f_i / V_i, averaged over the element by volume, then
// b_e = -F_fp,e / eps_e over the whole element. With the centre porosity
// (1 - eps_e) V_e = sum_i V_i the fluid receives -sum_i f_i / eps_e: 1/eps_e
// times the drag (coupling/source_term.hpp).
namespace fdem {

struct PaperSourceForm {
  // V_e b_e = -V_e (1 - eps_e) sum_i f_i / (eps_e sum_i V_i) (Eq. 20, 22).
  static double drag_to_fluid_force(double element_volume, double porosity, double solid_volume) {
    return -element_volume * (1.0 - porosity) / (porosity * solid_volume);
  }
  // Eq. 22: F / eps.
  static double exchange_coefficient(double coefficient_per_volume, double porosity) {
    return coefficient_per_volume / porosity;
  }
};

}  // namespace fdem

#pragma once
// The source forms (scene key coupling.source_form): how an element's drag
// becomes the fluid's force (paper Sect. 3, Eq. 20, 22; the element average
// and the nodal distribution are coupling/source_term.hpp's). One row each in
// source_form_table.cpp, each form's closures in its own header. The loader,
// `fdem check`, the run's summary, the checkpoint fingerprint and
// `fdem help scene` read the table; coupling/source_term.cpp (explicit
// exchange) and coupling/momentum_exchange.cpp (semi-implicit) call the closures.
#include <span>
#include <string_view>

#include "core/named_rows.hpp"

namespace fdem {

/// A form's code: its row in source_form_table.cpp (rows are only appended:
/// the position is the checkpoint fingerprint's value).
enum class SourceForm { paper, conservative };

struct SourceFormEntry : RegisteredTerm<SourceForm> {
  /// Explicit exchange: the factor that takes the drag summed over an
  /// element's grains, sum_i f_i [N], to the element's force on the fluid
  /// V_e b_e [N], from the element volume V_e [m^3], its porosity eps_e and
  /// its grains' volume sum_i V_i [m^3].
  double (*drag_to_fluid_force)(double element_volume, double porosity, double solid_volume);
  /// Semi-implicit exchange: the element's coefficient beta_e [kg/(m^3 s)]
  /// from the grains' summed drag coefficients per element volume
  /// sum_i c_i / V_e and the element porosity.
  double (*exchange_coefficient)(double coefficient_per_volume, double porosity);
};

/// Every form, in table order (= the enumeration's).
std::span<const SourceFormEntry> source_forms();
/// The row of a form.
inline const SourceFormEntry& source_form_entry(SourceForm f) { return row_of(source_forms(), f); }

}  // namespace fdem

#pragma once
// The porosity schemes (scene key coupling.porosity), one row each in
// porosity_scheme_table.cpp: the scene's word, its documentation, and the
// two choices coupling/porosity.cpp builds the field from (where a grain's
// solid goes; whether that is smoothed). The loader, `fdem check`, the run's
// summary, the checkpoint fingerprint and `fdem help scene` read the table;
// the formulas and their properties are in coupling/porosity.hpp.
#include <span>
#include <string_view>

#include "core/named_rows.hpp"

namespace fdem {

/// A scheme's code: its row in porosity_scheme_table.cpp (rows are only
/// appended: the position is the checkpoint fingerprint's value).
enum class PorosityScheme { centre, shape_function, diffused, intersection };

/// Where each grain's solid volume goes.
enum class SolidDeposit {
  element_of_centre,  // wholly to the element holding the centre (Eq. 32)
  element_overlap,    // to every element by the sphere's volume inside it (coupling/sphere_tetrahedron_volume.hpp)
  nodes_by_weights,   // to the element's 4 nodes with the P1 weights, then averaged back per element
};

struct PorositySchemeEntry : RegisteredTerm<PorosityScheme> {
  SolidDeposit deposit;
  /// The nodal solid fraction smoothed by one implicit diffusion over the
  /// smoothing length (coupling.porosity_smoothing_*; needs nodes_by_weights).
  bool smoothed;
};

/// Every scheme, in table order (= the enumeration's).
std::span<const PorositySchemeEntry> porosity_schemes();
/// The row of a scheme.
inline const PorositySchemeEntry& porosity_scheme_entry(PorosityScheme s) { return row_of(porosity_schemes(), s); }

}  // namespace fdem

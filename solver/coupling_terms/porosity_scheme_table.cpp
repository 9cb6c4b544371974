// The registered porosity schemes (coupling/porosity.hpp has each one's
// formulas, properties and cost). A new scheme is one enumerator and one row
// here, appended: a row's position is its code in checkpoint fingerprints.
#include <array>

#include "coupling_terms/porosity_scheme.hpp"

namespace fdem {

namespace {

using S = PorosityScheme;
using D = SolidDeposit;
constexpr std::array<PorositySchemeEntry, 4> kPorositySchemes{{
    {{S::centre, "centre", "Eq. 32", "Eq. 32"}, D::element_of_centre, false},
    {{S::shape_function, "shape_function", "P1 weights", "P1 weights"}, D::nodes_by_weights, false},
    {{S::diffused, "diffused", "that, smoothed over the smoothing length", "P1 weights, one implicit diffusion"},
     D::nodes_by_weights, true},
    {{S::intersection, "intersection", "exact sphere-tetrahedron volumes", "exact sphere-tetrahedron volumes"},
     D::element_overlap, false},
}};
static_assert(rows_in_code_order(std::span<const PorositySchemeEntry>(kPorositySchemes)));

}  // namespace

std::span<const PorositySchemeEntry> porosity_schemes() { return kPorositySchemes; }

}  // namespace fdem

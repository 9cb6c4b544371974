// The registered contact laws (each law's header has its formulas). A new
// law is one enumerator, one header and one row here, appended: a row's
// position is its code in checkpoint fingerprints.
#include <array>

#include "contact_laws/contact_law.hpp"

namespace fdem {

namespace {

using L = ContactLawKind;
constexpr std::array<ContactLawEntry, 1> kContactLaws{{
    {{L::linear_spring_dashpot, "linear_spring_dashpot",
      "f_n = Kn delta + Cn delta_dot (Eq. 6), Cn given or from the restitution e for each pair's effective mass",
      "linear spring-dashpot, Eq. 6"},
     "{kn, cn | restitution, kt, ct, friction}"},
}};
static_assert(rows_in_code_order(std::span<const ContactLawEntry>(kContactLaws)));

}  // namespace

std::span<const ContactLawEntry> contact_laws() { return kContactLaws; }

}  // namespace fdem

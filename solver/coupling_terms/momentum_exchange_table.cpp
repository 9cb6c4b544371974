// The registered momentum exchanges. A new one is one enumerator and one row
// here, appended (a row's position is its code in checkpoint fingerprints),
// and its branch of the coupled step in coupling/simulation.cpp.
#include <array>

#include "coupling_terms/momentum_exchange_form.hpp"

namespace fdem {

namespace {

constexpr std::array<MomentumExchangeEntry, 2> kMomentumExchanges{{
    {{MomentumExchange::explicit_drag, "explicit", "last step's mean drag as a body force",
      "explicit (last step's drag)"},
     false},
    {{MomentumExchange::semi_implicit, "semi_implicit",
      "beta_e u^{n+1} in the fluid matrix (coupling/momentum_exchange.hpp)",
      "semi-implicit (beta_e u^{n+1} in the fluid matrix)"},
     true},
}};
static_assert(rows_in_code_order(std::span<const MomentumExchangeEntry>(kMomentumExchanges)));

}  // namespace

std::span<const MomentumExchangeEntry> momentum_exchanges() { return kMomentumExchanges; }

}  // namespace fdem

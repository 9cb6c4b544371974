#pragma once
// How the fluid takes the drag (scene key coupling.exchange), a row each in
// momentum_exchange_table.cpp: explicit, last step's mean drag as a body
// force through the source form (coupling/source_term.hpp), or semi-implicit,
// beta_e (v_e - u^{n+1}) with beta_e in the fluid's matrix and the grains
// feeling the same frozen coefficient (coupling/momentum_exchange.hpp). Read
// by the loader, `fdem check`, the run's summary, the checkpoint fingerprint,
// `fdem help scene` and the coupled step (coupling/simulation.cpp).
#include <span>
#include <string_view>

#include "core/named_rows.hpp"

namespace fdem {

/// An exchange's code: its row in momentum_exchange_table.cpp (appended only:
/// the position is the checkpoint fingerprint's value).
enum class MomentumExchange { explicit_drag, semi_implicit };

struct MomentumExchangeEntry : RegisteredTerm<MomentumExchange> {
  /// beta_e goes into the fluid's matrix (coupling/momentum_exchange.hpp);
  /// otherwise the drag is a body force from coupling/source_term.hpp.
  bool coefficient_in_fluid_matrix;
};

/// Every exchange, in table order (= the enumeration's).
std::span<const MomentumExchangeEntry> momentum_exchanges();
/// The row of an exchange.
inline const MomentumExchangeEntry& momentum_exchange_entry(MomentumExchange e) { return row_of(momentum_exchanges(), e); }

}  // namespace fdem

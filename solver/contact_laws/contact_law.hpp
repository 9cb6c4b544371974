#pragma once
// The contact laws (scene key contact.law), one row each in
// contact_law_table.cpp: the scene's word, its documentation and the contact
// keys it reads. The loader, `fdem check`, the run's summary, the checkpoint
// fingerprint and `fdem help scene` read the table; each law's formulas are
// in its own header (linear_spring_dashpot.hpp), inline, so the DEM engine
// compiles its pair loop for the law (dem/dem_engine.cpp picks the kernel
// from the row's code once, at construction).
#include <span>
#include <string_view>

#include "core/named_rows.hpp"

namespace fdem {

/// A law's code: its row in contact_law_table.cpp (rows are only appended:
/// the position is the checkpoint fingerprint's value).
enum class ContactLawKind { linear_spring_dashpot };

struct ContactLawEntry : RegisteredTerm<ContactLawKind> {
  /// The contact keys the law reads, as a scene file gives them (the
  /// loader's message when the contact map is missing).
  std::string_view keys;
};

/// Every law, in table order (= the enumeration's).
std::span<const ContactLawEntry> contact_laws();
/// The row of a law.
inline const ContactLawEntry& contact_law_entry(ContactLawKind law) { return row_of(contact_laws(), law); }

}  // namespace fdem

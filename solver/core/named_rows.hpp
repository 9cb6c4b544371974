#pragma once
// What every registration table shares (drag_laws/drag_law_table.cpp,
// coupling_terms/*_table.cpp): a row carries the word a scene file uses
// (`name`), and a term with an enumerated code (coupling_terms/) carries it
// as `code`, the row's position in its table. These find a row by either and
// list the words for messages, so no table repeats them.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

namespace fdem {

/// The head of a registered term's row: its code (an enumeration whose
/// value i is row i), the scene's word, one line for the schema, and a few
/// words for `fdem run`'s physics summary.
template <class Code>
struct RegisteredTerm {
  Code code;
  std::string_view name;
  std::string_view doc;
  std::string_view summary;
};

/// The row named `name`, or nullptr.
template <class Row>
const Row* find_named_row(std::span<const Row> rows, std::string_view name) {
  for (const Row& row : rows)
    if (row.name == name) return &row;
  return nullptr;
}

/// "a, b, c": the rows' names in table order.
template <class Row>
std::string row_names(std::span<const Row> rows) {
  std::string names;
  for (const Row& row : rows) names += (names.empty() ? "" : ", ") + std::string(row.name);
  return names;
}

/// True when row i has code i (checked at compile time by each table).
template <class Row>
constexpr bool rows_in_code_order(std::span<const Row> rows) {
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (static_cast<std::size_t>(rows[i].code) != i) return false;
  return true;
}

/// The row of a code.
template <class Row, class Code>
const Row& row_of(std::span<const Row> rows, Code code) {
  return rows[static_cast<std::size_t>(code)];
}

}  // namespace fdem

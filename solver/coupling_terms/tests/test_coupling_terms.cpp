// The coupling's registered terms (coupling_terms/): each table's rows are
// found by their names, in the enumeration's order, and the source forms'
// closures give the closed forms of Eq. 22 and of momentum conservation.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "coupling_terms/momentum_exchange_form.hpp"
#include "coupling_terms/porosity_scheme.hpp"
#include "coupling_terms/source_form.hpp"

namespace fdem {
namespace {

// Row i of a table is found by its name, has code i, carries its documentation,
// and no two rows share a name.
template <class Row>
void expect_rows_named_once_in_order(std::span<const Row> rows) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const Row& row = rows[i];
    EXPECT_TRUE(names.insert(std::string(row.name)).second) << row.name << " twice";
    EXPECT_EQ(find_named_row(rows, row.name), &row) << row.name;
    EXPECT_EQ(&row_of(rows, row.code), &row) << row.name;
    EXPECT_EQ(static_cast<std::size_t>(row.code), i) << row.name;
    EXPECT_FALSE(row.doc.empty()) << row.name;
    EXPECT_FALSE(row.summary.empty()) << row.name;
  }
  EXPECT_EQ(find_named_row(rows, "not_a_term"), nullptr);
}

TEST(CouplingTerms, PorositySchemesAreNamedOnceInCodeOrder) {
  expect_rows_named_once_in_order(porosity_schemes());
  EXPECT_EQ(porosity_scheme_entry(PorosityScheme::centre).deposit, SolidDeposit::element_of_centre);  // Eq. 32
  // Smoothing works on the nodal field: only a nodal deposit can be smoothed.
  for (const PorositySchemeEntry& s : porosity_schemes()) {
    if (s.smoothed) {
      EXPECT_EQ(s.deposit, SolidDeposit::nodes_by_weights) << s.name;
    }
  }
}

TEST(CouplingTerms, SourceFormsAreNamedOnceInCodeOrder) { expect_rows_named_once_in_order(source_forms()); }

TEST(CouplingTerms, MomentumExchangesAreNamedOnceInCodeOrder) {
  expect_rows_named_once_in_order(momentum_exchanges());
  EXPECT_FALSE(momentum_exchange_entry(MomentumExchange::explicit_drag).coefficient_in_fluid_matrix);
  EXPECT_TRUE(momentum_exchange_entry(MomentumExchange::semi_implicit).coefficient_in_fluid_matrix);
}

// With the centre porosity an element's grains fill (1 - eps_e) V_e, so the
// paper's form gives the fluid -sum f / eps_e (Eq. 20, 22: 2.5 times the drag
// at eps 0.4) and the conservative one exactly -sum f, at any porosity.
TEST(CouplingTerms, SourceFormsGiveEq22AndNewtonsThirdLaw) {
  const double volume = 2.0e-9, eps = 0.4, solid = (1.0 - eps) * volume;
  const SourceFormEntry& paper = source_form_entry(SourceForm::paper);
  const SourceFormEntry& conservative = source_form_entry(SourceForm::conservative);
  EXPECT_NEAR(paper.drag_to_fluid_force(volume, eps, solid), -2.5, 1e-15);
  EXPECT_DOUBLE_EQ(conservative.drag_to_fluid_force(volume, eps, solid), -1.0);
  EXPECT_DOUBLE_EQ(conservative.drag_to_fluid_force(volume, 0.9, 0.3 * solid), -1.0);
  // Semi-implicit: beta_e = sum c / V_e, over eps for the paper's form (Eq. 22).
  EXPECT_DOUBLE_EQ(paper.exchange_coefficient(30.0, eps), 75.0);
  EXPECT_DOUBLE_EQ(conservative.exchange_coefficient(30.0, eps), 30.0);
}

}  // namespace
}  // namespace fdem

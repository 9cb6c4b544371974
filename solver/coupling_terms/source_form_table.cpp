// The registered source forms: one row each (the scene's word, doc line,
// summary, and the form's closures from its header). A new form is one
// header, one enumerator and one row here, appended: a row's position is its
// code in checkpoint fingerprints.
#include <array>

#include "coupling_terms/conservative_source_form.hpp"
#include "coupling_terms/paper_source_form.hpp"
#include "coupling_terms/source_form.hpp"

namespace fdem {

namespace {

template <class Form>
constexpr SourceFormEntry row(RegisteredTerm<SourceForm> term) {
  return {term, &Form::drag_to_fluid_force, &Form::exchange_coefficient};
}

constexpr std::array kSourceForms{
    row<PaperSourceForm>({SourceForm::paper, "paper", "Eq. 22, F/eps per element volume (simplified model only)",
                          "source term F/eps per element volume (Eq. 22)"}),
    row<ConservativeSourceForm>({SourceForm::conservative, "conservative", "exactly minus the grains' force",
                                 "conservative source term (exactly minus the grains' force)"}),
};
static_assert(rows_in_code_order(std::span<const SourceFormEntry>(kSourceForms)));

}  // namespace

std::span<const SourceFormEntry> source_forms() { return kSourceForms; }

}  // namespace fdem

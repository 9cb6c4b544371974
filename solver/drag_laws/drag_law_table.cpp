// The registered drag laws: one row each (name, doc line, the law's per-step
// fold and per-subcycle closure, and its subcycle kernel). The scene loader
// (effects.drag), `fdem check` and the checkpoint fingerprint read this
// table; a new law is one header in this folder and one row here, appended
// (a row's position is its code in checkpoint fingerprints).
#include <algorithm>
#include <array>
#include <stdexcept>

#include "core/named_rows.hpp"
#include "drag_laws/beetstra.hpp"
#include "drag_laws/di_felice.hpp"
#include "drag_laws/drag_kernel.hpp"
#include "drag_laws/drag_law.hpp"
#include "drag_laws/ergun_wen_yu.hpp"
#include "drag_laws/rong.hpp"
#include "drag_laws/stokes.hpp"

namespace fdem {

namespace {

template <class Law>
constexpr DragLawEntry row(std::string_view name, std::string_view doc) {
  double subcycle_error = 0.0;
  if constexpr (requires { Law::subcycle_error; }) subcycle_error = Law::subcycle_error;
  return {name, doc, &Law::fold, &Law::coefficient, &drag_subcycle<Law>, subcycle_error};
}

const std::array kDragLaws{
    row<ErgunWenYu>("ergun_wen_yu", "Ergun below eps 0.8, Wen & Yu above, Rowe & Henwood Cd (the paper's Eq. 11-15; Gidaspow 1994)"),
    row<Stokes>("stokes", "3 pi mu d (u - v), any eps: the analytic Stokes limit"),
    row<DiFelice>("di_felice", "Dallavalle Cd at the superficial slip times the voidage function eps^-chi (Di Felice 1994)"),
    row<Beetstra>("beetstra", "lattice-Boltzmann fit for mono-disperse arrays, phi <= 0.6, Re <= 1000 (Beetstra et al. 2007)"),
    row<Rong>("rong", "Di Felice's form with chi refitted to packed beds, eps 0.37-0.98 (Rong, Dong, Yu 2013)"),
};

}  // namespace

std::span<const DragLawEntry> drag_laws() { return kDragLaws; }

const DragLawEntry* find_drag_law(std::string_view name) { return find_named_row(drag_laws(), name); }

const DragLawEntry& drag_law(std::string_view name) {
  if (const DragLawEntry* law = find_drag_law(name)) return *law;
  throw std::invalid_argument("unknown drag law '" + std::string(name) + "' (known: " + drag_law_names() + ")");
}

std::size_t drag_law_index(const DragLawEntry& law) { return static_cast<std::size_t>(&law - kDragLaws.data()); }

std::string drag_law_names() { return row_names(drag_laws()); }

}  // namespace fdem

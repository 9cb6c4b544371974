#pragma once
// Numerical uncertainty of one result from three systematic refinements
// (mesh or time step, constant ratio r): Roache's grid convergence index as
// used by ASME V&V 20-2009 (Sect. 5), the u_num the report puts beside each
// validation comparison E = S - D.
//
//   observed order  p = ln((f3 - f2) / (f2 - f1)) / ln r     (f1 finest)
//   GCI_fine        = Fs |f2 - f1| / (r^p - 1)
//   u_num           = GCI_fine / 1.15   (V&V 20: the GCI read as an expanded
//                                        uncertainty, factor 1.15)
// with p = min(observed, formal order) and Fs = 1.25 when the observed order
// is at least 0.5 ("monotone"); below that (or negative: differences that
// grow under refinement) the order is not confirmed and Roache's Fs = 3 with
// the formal order is used ("unconfirmed"). Oscillatory refinement ((f3 - f2)
// and (f2 - f1) of opposite sign) has no order; u_num is then half the range
// of the three (Stern et al. 2001), flagged "oscillatory".
#include <algorithm>
#include <cmath>
#include <string>

namespace fdem::study {

struct RefinementUncertainty {
  double observed_order = std::nan("");  // NaN unless monotone
  double gci_fine = std::nan("");        // in the unit of f
  double u_num = std::nan("");           // standard uncertainty, unit of f
  std::string kind;                      // monotone | unconfirmed | oscillatory | converged
};

/// f1 finest, f3 coarsest, r > 1 the refinement ratio between neighbours,
/// `formal_order` the scheme's order in the refined parameter.
inline RefinementUncertainty refinement_uncertainty(double f1, double f2, double f3, double r, double formal_order) {
  constexpr double expansion = 1.15;
  RefinementUncertainty u;
  const double e21 = f2 - f1, e32 = f3 - f2;
  const double scale = std::max({std::abs(f1), std::abs(f2), std::abs(f3)});
  // Differences at round-off of the values: nothing left to estimate.
  if (std::abs(e21) <= 1e-14 * scale && std::abs(e32) <= 1e-14 * scale) {
    u.kind = "converged";
    u.observed_order = std::nan("");
    u.gci_fine = u.u_num = 0.0;
    return u;
  }
  if (e21 * e32 <= 0.0) {
    u.kind = "oscillatory";
    u.u_num = 0.5 * (std::max({f1, f2, f3}) - std::min({f1, f2, f3}));
    u.gci_fine = expansion * u.u_num;
    return u;
  }
  u.observed_order = std::log(e32 / e21) / std::log(r);
  const bool confirmed = u.observed_order >= 0.5;
  u.kind = confirmed ? "monotone" : "unconfirmed";
  const double p = confirmed ? std::min(u.observed_order, formal_order) : formal_order;
  const double safety_factor = confirmed ? 1.25 : 3.0;
  u.gci_fine = safety_factor * std::abs(e21) / (std::pow(r, p) - 1.0);
  u.u_num = u.gci_fine / expansion;
  return u;
}

}  // namespace fdem::study

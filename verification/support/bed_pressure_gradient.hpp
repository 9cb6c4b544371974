#pragma once
// The pressure gradient through a uniform bed of spheres (porosity eps,
// diameter d, grains at rest) for the superficial velocity U, as the two
// fluid models give it; shared by the packed beds (verification/packed_bed)
// and the fluidized bed (verification/fluidized_bed).
//
// Volume-averaged fluid: -eps dp/dz carries the drag, beta (U / eps) per bed
// volume with the paper's Ergun branch of Eq. 12, which is Ergun (1952, Eq. 1):
//   -dp/dz = 150 (1-eps)^2 mu U / (eps^3 d^2) + 1.75 (1-eps) rho U^2 / (eps^3 d).
// Simplified model (Eq. 21-22): div u = 0 keeps u = U in the bed, so the drag
// of Eq. 12 sees U and the paper's source F / eps is carried by -dp/dz alone:
// Ergun's viscous term times eps and its inertial term times eps^2.

namespace fdem::verification {

/// Ergun's -dp/dz [Pa/m].
double ergun_gradient(double eps, double U, double d, double rho, double mu);

/// The simplified model's -dp/dz [Pa/m].
double simplified_gradient(double eps, double U, double d, double rho, double mu);

}  // namespace fdem::verification

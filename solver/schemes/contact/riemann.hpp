// Pairwise contact solutions of the Godunov-type contact SPH (seed 003: Parshikov, Medin, Rublev &
// Dyachkov, "Adjusting the numerical viscosity in the Godunov-like SPH method at modeling
// compressible flows"; the method of Parshikov & Medin 2002, J. Comput. Phys. 180, 358).
//
//   acoustic_riemann   eqs. (8)-(9): contact pressure P* and normal contact velocity U*R of the
//                      acoustic Riemann problem between particles i and j, impedances Z = rho C.
//   viscous_contact    eqs. (27) and (30)-(32): the contact velocity and the effective viscosity
//                      of two Newtonian fluids (eta_i, rho_i) | (eta_j, rho_j) in contact.
//
// Conventions: e^R points from i to j (e^R = (r_j - r_i) / |r_j - r_i|), U^R = U . e^R, so
// U_i^R > U_j^R means the particles approach and P* > (Z_j P_i + Z_i P_j) / (Z_i + Z_j).
//
// Eq. (27) rewritten: with s = sqrt(nu_i / nu_j), eta_j s = sqrt(eta_i / rho_i) b_j where
// b = sqrt(eta rho), so U* = (b_i U_i + b_j U_j) / (b_i + b_j). Eqs. (30)-(32) share the factor
// eta_i eta_j (1 + s) / (eta_i + eta_j s) = b_i b_j (sqrt(nu_i) + sqrt(nu_j)) / (b_i + b_j),
// which is eta for two equal fluids and 0 when either fluid is inviscid. This symmetric form is the
// same number without the 0/0 of nu_i / nu_j at eta = 0.
#pragma once

#include <cmath>

namespace sph::contact {

struct RiemannSolution {
  double P; // P*_ij, eq. (8)
  double U; // U*R_ij, eq. (9), along e^R (from i to j)
};

// Eqs. (8)-(9). uRi, uRj: normal velocities U . e^R; Zi, Zj > 0.
inline RiemannSolution acoustic_riemann(double Pi, double uRi, double Zi, double Pj, double uRj,
                                        double Zj) {
  const double inv = 1.0 / (Zi + Zj);
  return {(Pj * Zi + Pi * Zj - Zi * Zj * (uRj - uRi)) * inv, (uRi * Zi + uRj * Zj - Pj + Pi) * inv};
}

// Per-particle viscous data of eqs. (27)-(32): b = sqrt(eta rho), sqrt_nu = sqrt(eta / rho).
struct ViscousSide {
  double b = 0.0;
  double sqrt_nu = 0.0;
};
inline ViscousSide viscous_side(double eta, double rho) {
  return eta > 0.0 ? ViscousSide{std::sqrt(eta * rho), std::sqrt(eta / rho)} : ViscousSide{};
}

// The factor of eqs. (30)-(32): tau^RR* = 4/3 eta_ij (U_j^R - U_i^R) / |r_ij|,
// tau^SR* = eta_ij (U_j^S - U_i^S) / |r_ij| (and T like S).
inline double contact_viscosity(const ViscousSide& i, const ViscousSide& j) {
  const double bs = i.b + j.b;
  return bs > 0.0 ? i.b * j.b * (i.sqrt_nu + j.sqrt_nu) / bs : 0.0;
}

// The weight of particle i in the contact velocity of eq. (27), U* = w U_i + (1 - w) U_j.
// Two inviscid fluids (b_i = b_j = 0) take the acoustic weight Z_i / (Z_i + Z_j) of eq. (9).
inline double contact_weight(const ViscousSide& i, const ViscousSide& j, double Zi, double Zj) {
  const double bs = i.b + j.b;
  return bs > 0.0 ? i.b / bs : Zi / (Zi + Zj);
}

} // namespace sph::contact

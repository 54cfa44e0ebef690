// The viscous Laplacian chosen by the study's string (visc = "visc01".."visc04", or "visc03t":
// VISC-03 with the tensor reading of its factor H_bb^{-1} / kappa, see visc03.hpp; or "visc02p":
// VISC-02 with the weight of eq. (16) as printed, sign and factor made consistent, visc02.hpp),
// seed 001 section 3. Owns the work arrays the corrected forms need (Gamma, tr B, grad u), so a
// scheme calls
//   lap.prepare(nl, V)     once per particle configuration (Gamma, tr B: VISC-03/03t/04), then
//   lap.apply(nl, V, u, out) for each field (every call after the first allocates nothing).
#pragma once

#include "operators/correction_matrix.hpp"
#include "operators/visc01.hpp"
#include "operators/visc02.hpp"
#include "operators/visc03.hpp"
#include "operators/visc04.hpp"

#include <stdexcept>
#include <string>
#include <vector>

namespace sph {

// In the order of visc_names(); new forms are appended so the existing names keep their values.
enum class ViscForm { Visc01, Visc02, Visc03, Visc04, Visc03Tensor, Visc02Printed };

inline const std::vector<std::string>& visc_names() {
  static const std::vector<std::string> names{"visc01", "visc02",  "visc03",
                                              "visc04", "visc03t", "visc02p"};
  return names;
}

inline ViscForm parse_visc(const std::string& name) {
  const auto& n = visc_names();
  for (std::size_t k = 0; k < n.size(); ++k)
    if (n[k] == name)
      return static_cast<ViscForm>(k);
  throw std::invalid_argument("unknown viscous Laplacian '" + name + "'");
}

template <int D, class T, class Kernel>
class ViscousLaplacian {
public:
  ViscousLaplacian(ViscForm form, const Kernel& kernel, double eta)
      : form_(form), kernel_(kernel), eta2_(eta * eta) {}

  ViscForm form() const { return form_; }
  const std::vector<Mat<D>>& gamma() const { return gamma_; }

  // Per-configuration work: the correction matrix for VISC-03 (both readings) and VISC-04.
  template <class Select = AllParticles>
  void prepare(const NeighborList<D>& nl, const std::vector<double>& V, Select select = {}) {
    if (form_ == ViscForm::Visc01 || form_ == ViscForm::Visc02 || form_ == ViscForm::Visc02Printed)
      return;
    gamma_.resize(nl.num_particles());
    h_bb_.resize(nl.num_particles());
    CorrectionMatrix<D> op{V, gamma_, h_bb_};
    interact(nl, op, select);
  }

  template <class Select = AllParticles>
  void apply(const NeighborList<D>& nl, const std::vector<double>& V, const std::vector<T>& u,
             std::vector<T>& out, Select select = {}) {
    out.resize(u.size());
    switch (form_) {
    case ViscForm::Visc01: {
      Visc01<D, T> op{V, u, eta2_, out};
      interact(nl, op, select);
      break;
    }
    case ViscForm::Visc02: {
      Visc02<D, T, Kernel> op{V, u, kernel_, out};
      interact(nl, op, select);
      break;
    }
    case ViscForm::Visc02Printed: {
      Visc02Printed<D, T, Kernel> op{V, u, kernel_, out};
      interact(nl, op, select);
      break;
    }
    case ViscForm::Visc03:
    case ViscForm::Visc03Tensor: {
      grad_u_.resize(u.size());
      CorrectedGradient<D, T> g{V, gamma_, u, grad_u_};
      interact(nl, g, select);
      const Visc03Reading reading =
          form_ == ViscForm::Visc03Tensor ? Visc03Reading::Tensor : Visc03Reading::Scalar;
      Visc03<D, T> op{V, u, grad_u_, h_bb_, gamma_, reading, eta2_, out};
      interact(nl, op, select);
      break;
    }
    case ViscForm::Visc04: {
      Visc04<D, T> op{V, u, gamma_, eta2_, out};
      interact(nl, op, select);
      break;
    }
    }
  }

private:
  ViscForm form_;
  Kernel kernel_;
  double eta2_;
  std::vector<Mat<D>> gamma_;
  std::vector<double> h_bb_;
  std::vector<Grad<D, T>> grad_u_;
};

} // namespace sph

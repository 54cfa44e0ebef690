// Kernel registry: the study's string (kernel = "wendland_c2") picks the kernel once per job;
// the chosen type is then a template argument of the hot loops (no virtual call per pair).
//
//   with_kernel<D>("cubic_spline", h, [&](const auto& W) { ...loops over pairs with W... });
//
// Adding a kernel: one header in this folder named like its key, one line in kernel_names() and
// one branch in with_kernel().
#pragma once

#include "core/kernels/cubic_spline.hpp"
#include "core/kernels/quintic_spline.hpp"
#include "core/kernels/wendland_c2.hpp"

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sph {

inline const std::vector<std::string>& kernel_names() {
  static const std::vector<std::string> names{"cubic_spline", "quintic_spline", "wendland_c2"};
  return names;
}

// Support radius in units of h, without building a kernel.
inline double kernel_support_factor(std::string_view name) {
  if (name == "cubic_spline")
    return CubicSpline<2>::support_factor;
  if (name == "quintic_spline")
    return QuinticSpline<2>::support_factor;
  if (name == "wendland_c2")
    return WendlandC2<2>::support_factor;
  throw std::invalid_argument("unknown kernel '" + std::string(name) + "'");
}

template <int D, class F>
decltype(auto) with_kernel(std::string_view name, double h, F&& f) {
  if (name == "cubic_spline")
    return f(CubicSpline<D>(h));
  if (name == "quintic_spline")
    return f(QuinticSpline<D>(h));
  if (name == "wendland_c2")
    return f(WendlandC2<D>(h));
  throw std::invalid_argument("unknown kernel '" + std::string(name) + "'");
}

} // namespace sph

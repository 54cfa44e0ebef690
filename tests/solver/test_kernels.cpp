// Kernels: unit integral on a fine lattice, gradient antisymmetry, zero sum and unit first moment
// of the gradient (sum_j V_j (r_j - r_i) (x) grad W = I), compact support, continuity at the piece
// boundaries, and derivatives against finite differences; 2D and 3D.
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;

namespace {

template <int D>
void check_kernel(const std::string& name) {
  SCOPED_TRACE(name + " D=" + std::to_string(D));
  const double h = 1.0;
  with_kernel<D>(name, h, [&](const auto& W) {
    // Lattice sums over cell-centred points around the origin (offset by half a cell, so the
    // origin is not a lattice point and the sums are symmetric).
    const double dx = D == 2 ? 0.01 : 0.04;
    const int n = static_cast<int>(std::ceil(W.support() / dx)) + 1;
    std::array<int, D> lo, hi;
    lo.fill(-n), hi.fill(n);
    const Vec<D> xi = Vec<D>::Constant(0.5 * dx); // "particle i" at a lattice point
    double sum = 0.0;
    Vec<D> gsum = Vec<D>::Zero();
    Mat<D> moment = Mat<D>::Zero();
    const double vol = std::pow(dx, D);
    for_each_lattice_point<D>(lo, hi, dx, [&](const Vec<D>& xj, const std::array<int, D>&) {
      const Vec<D> rij = xi - xj;
      const double r = rij.norm();
      sum += vol * W.W(r);
      if (r > 0) {
        const Vec<D> g = W.dW(r) / r * rij;
        gsum += vol * g;
        moment += vol * g * (xj - xi).transpose();
      }
    });
    EXPECT_NEAR(sum, 1.0, 1e-6);
    EXPECT_LT(gsum.norm(), 1e-10);
    EXPECT_LT((moment - Mat<D>::Identity()).norm(), 1e-5);

    // Antisymmetry of the gradient: grad_i W(r_i - r_j) = -grad_j W(r_j - r_i).
    Vec<D> rij;
    for (int a = 0; a < D; ++a)
      rij[a] = 0.3 + 0.2 * a;
    const double r = rij.norm();
    const Vec<D> gi = W.dW(r) / r * rij, gj = W.dW(r) / r * Vec<D>(-rij);
    EXPECT_LT((gi + gj).norm(), 1e-15 * gi.norm());
    EXPECT_LT(gi.dot(rij), 0.0); // points from j towards i's decreasing weight

    // Compact support and smoothness.
    const double s = W.support();
    EXPECT_EQ(W.W(s), 0.0);
    EXPECT_EQ(W.W(1.5 * s), 0.0);
    EXPECT_EQ(W.dW(1.01 * s), 0.0);
    EXPECT_NEAR(W.W(s * (1 - 1e-9)), 0.0, 1e-12);
    EXPECT_GT(W.W(0.0), 0.0);
    EXPECT_NEAR(W.dW(0.0), 0.0, 1e-12);
    for (double q = 0.05; q < s; q += 0.05) {
      const double e = 1e-6;
      EXPECT_NEAR(W.dW(q), (W.W(q + e) - W.W(q - e)) / (2 * e), 1e-7 * W.W(0));
      // W''' jumps at the piece boundaries: the centred difference of dW is only O(e) there.
      const bool near_break = std::abs(q - std::round(q)) < 1e-3;
      if (!near_break)
        EXPECT_NEAR(W.d2W(q), (W.dW(q + e) - W.dW(q - e)) / (2 * e), 1e-6 * W.W(0));
      EXPECT_LE(W.dW(q), 0.0); // monotone decreasing
    }
    // Continuity across the piece boundaries q = 1, 2.
    for (double b : {1.0, 2.0}) {
      if (b >= s)
        continue;
      EXPECT_NEAR(W.W(b - 1e-12), W.W(b + 1e-12), 1e-9);
      EXPECT_NEAR(W.dW(b - 1e-12), W.dW(b + 1e-12), 1e-9);
    }
    // Scaling with h: W_h(r) = W_1(r / h) / h^D.
    with_kernel<D>(name, 2.0, [&](const auto& W2) {
      EXPECT_NEAR(W2.W(1.3), W.W(0.65) / std::pow(2.0, D), 1e-14);
    });
  });
}

} // namespace

TEST(Kernels, CubicSpline2D) {
  check_kernel<2>("cubic_spline");
}
TEST(Kernels, CubicSpline3D) {
  check_kernel<3>("cubic_spline");
}
TEST(Kernels, QuinticSpline2D) {
  check_kernel<2>("quintic_spline");
}
TEST(Kernels, QuinticSpline3D) {
  check_kernel<3>("quintic_spline");
}
TEST(Kernels, WendlandC22D) {
  check_kernel<2>("wendland_c2");
}
TEST(Kernels, WendlandC23D) {
  check_kernel<3>("wendland_c2");
}

TEST(Kernels, RegistryRejectsUnknownNames) {
  EXPECT_THROW(with_kernel<2>("gaussian", 1.0, [](const auto&) { return 0; }),
               std::invalid_argument);
  EXPECT_EQ(kernel_names().size(), 3u);
  for (const auto& n : kernel_names())
    EXPECT_GT(kernel_support_factor(n), 1.0);
}

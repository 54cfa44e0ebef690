// Value tests of the operators every scheme builds on (issue 15, section 1), each against a known
// answer with a tolerance derived from the operator's truncation error (said at each test):
//  - kernels: closed-form values of W, dW/dr, d2W/dr2 at specific points, and the normalisation
//    integral by radial quadrature (1e-10, independent of the lattice sums of test_kernels);
//  - VISC-01 and VISC-02 on a uniform lattice: for a quadratic field both are the exact Laplacian
//    times a lattice quadrature factor computed here from the kernel alone (round-off tolerance);
//  - VISC-01..04 on a smooth field on the uniform lattice: the error of the normalised forms
//    (VISC-03/04) is the leading smoothing error k^2 m4 / (12 m2) of a Fourier mode, predicted
//    from the lattice's own moments;
//  - VISC-01..04 on the disordered lattice (seed 001, section 4): absolute bounds, and a value
//    band for VISC-03's tensor reading (visc03t);
//  - the two readings of VISC-03's factor as exact identities of the second moment B_i;
//  - the ISPH divergence (eq. 4) and corrected pressure gradient (eqs. 10-11, 18) on linear fields;
//  - the ISPH PPE (eqs. 13-14) against a manufactured solution on a periodic lattice.
#include "core/cell_list.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "operators/summation_density.hpp"
#include "operators/viscous_laplacian.hpp"
#include "operators/wall_velocity.hpp"
#include "schemes/isph/isph.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

using namespace sph;

namespace {

constexpr double pi = std::numbers::pi;

// ---------------------------------------------------------------------------------------------
// Kernels

// Radial integral of W over the plane (2 pi r W) or space (4 pi r^2 W), composite Simpson on
// [0, support] with 2e5 intervals. The kernels are piecewise polynomials of degree <= 5 with
// breaks at integer q; Simpson's error on a piece is (b - a) dr^4 max|f''''| / 180, below 1e-15 at
// dr = 1.5e-5 h, and the kinks at the breaks (where f'''' jumps, an O(dr^4) effect per break) cost
// far less than 1e-10. So the tolerance 1e-10 pins the normalisation constant to 1e-10, while a
// 1 % error in sigma is 1e-2.
template <int D, class K>
double radial_integral(const K& W) {
  const int n = 200000;
  const double s = W.support(), dr = s / n;
  auto f = [&](double r) { return (D == 2 ? 2 * pi * r : 4 * pi * r * r) * W.W(r); };
  double sum = f(0) + f(s);
  for (int k = 1; k < n; ++k)
    sum += (k % 2 ? 4.0 : 2.0) * f(k * dr);
  return sum * dr / 3.0;
}

struct PointValue {
  double q, W, dW, d2W; // in units of sigma, sigma / h, sigma / h^2
};

// sigma and the point values, worked by hand from the formulas of the papers cited in each
// kernel's header (not from the code): exact to round-off, so tolerance 1e-13 relative.
template <int D, class K>
void check_points(const K& W, double sigma_h_D, const std::vector<PointValue>& pts) {
  const double h = W.h, sigma = sigma_h_D / std::pow(h, D);
  for (const auto& v : pts) {
    SCOPED_TRACE("q = " + std::to_string(v.q));
    const double r = v.q * h;
    EXPECT_NEAR(W.W(r), v.W * sigma, 1e-13 * sigma);
    EXPECT_NEAR(W.dW(r), v.dW * sigma / h, 1e-13 * sigma / h);
    EXPECT_NEAR(W.d2W(r), v.d2W * sigma / (h * h), 1e-13 * sigma / (h * h));
  }
  EXPECT_NEAR(radial_integral<D>(W), 1.0, 1e-10);
}

// ---------------------------------------------------------------------------------------------
// Lattices

// A unit box of n^D sampled (Fluid) particles and enough padding (Buffer, carrying the field) that
// no sampled particle sees a truncated support; optionally disordered (seed 001, section 4).
template <int D>
struct Lattice {
  Particles<D> p;
  NeighborList<D> nl;
  CubicSpline<D> kernel;
  double dx;

  Lattice(int n, double disorder, std::uint64_t seed, double h_over_dx = 1.2)
      : kernel(h_over_dx / n), dx(1.0 / n) {
    const int pad = static_cast<int>(std::ceil(kernel.support() / dx)) + 1;
    std::array<int, D> lo, hi;
    lo.fill(-pad), hi.fill(n + pad);
    UniformRandom rn(seed);
    for_each_lattice_point<D>(lo, hi, dx, [&](Vec<D> x, const std::array<int, D>& i) {
      bool inside = true;
      for (int a = 0; a < D; ++a)
        inside = inside && i[a] >= 0 && i[a] < n;
      for (int a = 0; a < D; ++a)
        x[a] += (rn() - 0.5) * disorder * dx;
      p.add(x, std::pow(dx, D), 1.0, inside ? Kind::Fluid : Kind::Buffer);
    });
    CellList<D> cells(Domain<D>{}, kernel.support());
    cells.build(p);
    nl.build(cells, p.r, kernel);
  }
  bool fluid(std::size_t i) const { return p.kind[i] == Kind::Fluid; }
  auto sampled() const {
    return [this](std::size_t i) { return fluid(i); };
  }
  template <class F>
  std::vector<double> field(F f) const {
    std::vector<double> out(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      out[i] = f(p.r[i]);
    return out;
  }
  std::vector<double> laplacian(ViscForm form, const std::vector<double>& f, double eta = 0.0) {
    ViscousLaplacian<D, double, CubicSpline<D>> lap(form, kernel, eta);
    std::vector<double> out(p.size(), 0.0);
    lap.prepare(nl, p.V, sampled());
    lap.apply(nl, p.V, f, out, sampled());
    return out;
  }
};

// Lattice sums over the offsets of a perfect 2D lattice of spacing dx (computed from the kernel
// alone, not through the operators): S1 = -sum V r dW (= tr B, -> D in the continuum), S2 =
// sum V lap W r^2 (-> 2 D), lap W = d2W + (D - 1) dW / r.
struct LatticeSums {
  double S1 = 0.0, S2 = 0.0, S3 = 0.0;
};
LatticeSums lattice_sums_2d(const CubicSpline<2>& W, double dx) {
  LatticeSums s;
  const int n = static_cast<int>(std::ceil(W.support() / dx)) + 1;
  for (int a = -n; a <= n; ++a)
    for (int b = -n; b <= n; ++b) {
      if (a == 0 && b == 0)
        continue;
      const double r = dx * std::hypot(a, b), V = dx * dx;
      s.S1 -= V * r * W.dW(r);
      s.S2 += V * (W.d2W(r) + W.dW(r) / r) * r * r;
      s.S3 += V * (W.d2W(r) - W.dW(r) / r) * r * r;
    }
  return s;
}

} // namespace

// ---------------------------------------------------------------------------------------------

TEST(KernelValues, CubicSpline) {
  // Monaghan 1992: sigma_2 = 10 / (7 pi), sigma_3 = 1 / pi; W = 1 - 3/2 q^2 + 3/4 q^3 (q < 1),
  // (2 - q)^3 / 4 (1 <= q < 2).
  const std::vector<PointValue> pts{{0.0, 1.0, 0.0, -3.0},
                                    {0.5, 1 - 0.375 + 0.09375, -1.5 + 0.5625, -3 + 2.25},
                                    {1.0, 0.25, -0.75, 1.5},
                                    {1.5, 0.125 / 4, -0.75 * 0.25, 0.75},
                                    {2.0, 0.0, 0.0, 0.0}};
  check_points<2>(CubicSpline<2>(0.7), 10.0 / (7.0 * pi), pts);
  check_points<3>(CubicSpline<3>(0.7), 1.0 / pi, pts);
}

TEST(KernelValues, QuinticSpline) {
  // Morris et al. 1997: sigma_2 = 7 / (478 pi), sigma_3 = 1 / (120 pi);
  // W = (3-q)^5 - 6 (2-q)^5 + 15 (1-q)^5 (brackets only while positive).
  const std::vector<PointValue> pts{{0.0, 243 - 192 + 15, -5 * (81 - 96 + 15), 20 * (27 - 48 + 15)},
                                    {1.0, 32 - 6, -5 * (16 - 6), 20 * (8 - 6)},
                                    {2.0, 1, -5, 20},
                                    {2.5, 1.0 / 32, -5.0 / 16, 20.0 / 8},
                                    {3.0, 0, 0, 0}};
  check_points<2>(QuinticSpline<2>(0.3), 7.0 / (478.0 * pi), pts);
  check_points<3>(QuinticSpline<3>(0.3), 1.0 / (120.0 * pi), pts);
}

TEST(KernelValues, WendlandC2) {
  // Wendland 1995: sigma_2 = 7 / (4 pi), sigma_3 = 21 / (16 pi); W = (1 - q/2)^4 (2q + 1).
  const std::vector<PointValue> pts{{0.0, 1.0, 0.0, -5.0},
                                    {1.0, 3.0 / 16, -5.0 / 8, 5.0 / 4},
                                    {1.5, 4.0 / 256, -7.5 / 64, 10.0 / 16},
                                    {2.0, 0, 0, 0}};
  check_points<2>(WendlandC2<2>(1.1), 7.0 / (4.0 * pi), pts);
  check_points<3>(WendlandC2<3>(1.1), 21.0 / (16.0 * pi), pts);
}

// A quadratic f = 1/2 x^T H x + b . x + c on a perfect lattice: u_ij = u_i - u_j has no
// odd-moment contribution (the lattice is point-symmetric) and no error above second order, so
//   VISC-01 = 2 sum V (r dW / r^2) (-1/2 r^T H r) = tr H  S1 / D,
//   VISC-02 = sum V lap W (1/2 r^T H r)          = tr H  S2 / (2 D),
//   visc02p = 2 / (D + 2) sum V (W'' - W'/r) (1/2 r^T H r) = tr H  S3 / (D (D + 2)),
// with S1, S2, S3 the lattice sums above (the lattice's quadrature factors, 1 in the continuum),
// exactly up to round-off (tolerance 1e-10 relative). A factor or sign error in either operator
// changes the result by O(1).
TEST(ViscValues, Visc01And02OnQuadraticEqualTheQuadratureFactorOnUniformLattice) {
  Lattice<2> L(16, 0.0, 1);
  const auto f =
      L.field([](const Vec2& x) { return 3 * x[0] * x[0] - x[0] * x[1] + 2 * x[1] * x[1] + x[0]; });
  const double trH = 2 * 3 + 2 * 2;
  const LatticeSums s = lattice_sums_2d(L.kernel, L.dx);
  // The factors themselves: the cubic spline at h = 1.2 dx integrates r dW and lap W r^2 to within
  // a few % of the continuum (a value to compare against, not a tolerance of the operators).
  EXPECT_NEAR(s.S1 / 2, 1.0, 0.05);
  EXPECT_NEAR(s.S2 / 4, 1.0, 0.1);
  EXPECT_NEAR(s.S3 / 8, 1.0, 0.1);
  const auto l1 = L.laplacian(ViscForm::Visc01, f);
  const auto l2 = L.laplacian(ViscForm::Visc02, f);
  const auto l2p = L.laplacian(ViscForm::Visc02Printed, f);
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.fluid(i)) {
      ASSERT_NEAR(l1[i], trH * s.S1 / 2, 1e-10 * trH) << i;
      ASSERT_NEAR(l2[i], trH * s.S2 / 4, 1e-10 * trH) << i;
      ASSERT_NEAR(l2p[i], trH * s.S3 / 8, 1e-10 * trH) << i;
    }
}

// A Fourier mode f = sin(k x) on a perfect lattice. Every form is a sum of weights w_j times
// (f_j - f_i); Taylor-expanding f_j about x_i, the odd terms cancel and
//   L f = [sum w r_x^2 / 2] f'' + [sum w r_x^4 / 24] f'''' + O(k^6 h^6),
// so with the quadratic normalisation sum w r_x^2 = 2 (exact for VISC-03/04, see test_operators)
// the relative error is e_pred = -k^2 m4 / (12 m2) with m_p = sum_j w_j r_x^p, computed here from
// the weights of VISC-04 (w_j = -2 V_j (r_ij . Gamma_i grad W) / r^2). The next term is
// O((k h)^4 / 360 m6/m2) ~ 1e-4 at k h = 0.38; tolerance: 3 % of e_pred plus 2e-4.
TEST(ViscValues, NormalisedFormsOnFourierModeMatchTheirTruncationError) {
  Lattice<2> L(20, 0.0, 1);
  const double k = 2 * pi;
  const auto f = L.field([&](const Vec2& x) { return std::sin(k * x[0]); });
  std::vector<Mat<2>> gamma(L.p.size());
  std::vector<double> trb(L.p.size());
  CorrectionMatrix<2> cm{L.p.V, gamma, trb};
  interact(L.nl, cm, L.sampled());
  for (ViscForm form : {ViscForm::Visc03, ViscForm::Visc04}) {
    const auto lap = L.laplacian(form, f);
    double worst = 0.0;
    int checked = 0;
    for (std::size_t i = 0; i < L.p.size(); ++i) {
      if (!L.fluid(i) || std::abs(f[i]) < 0.5)
        continue; // relative error where |f| is not small
      double m2 = 0, m4 = 0;
      for (auto q = L.nl.offset[i]; q < L.nl.offset[i + 1]; ++q) {
        const auto pr = L.nl.pair(q);
        const double w = -2 * L.p.V[pr.j] * pr.r_ij.dot(gamma[i] * pr.grad()) / (pr.r * pr.r);
        const double rx2 = pr.r_ij[0] * pr.r_ij[0];
        m2 += w * rx2, m4 += w * rx2 * rx2;
      }
      const double exact = -k * k * f[i];
      const double e_pred = -k * k * m4 / (12 * m2), e = (lap[i] - exact) / exact;
      ASSERT_NEAR(e, e_pred, 0.03 * std::abs(e_pred) + 2e-4) << i;
      worst = std::max(worst, std::abs(e));
      ++checked;
    }
    EXPECT_GT(checked, 100);
    // The size of the error itself: e_pred = k^2 m4 / (12 m2) with m4 / m2 = 0.93 h^2 for this
    // kernel and lattice (from the sums above), so 0.011 at k h = 0.377 (printed).
    std::printf("%s: max relative error %.5f\n", form == ViscForm::Visc03 ? "visc03" : "visc04",
                worst);
    EXPECT_NEAR(worst, 0.011, 0.002);
  }
}

// The disordered lattice of seed 001 (section 4: r + (Rn - 0.5) dx) with f = x^4 + y^4 (the
// patch test's field), mean relative error over the sampled particles. For the first-order
// consistent VISC-03 the residual error is the anisotropy of the particles' discrete second moment
// (the first-order error is removed by the gradient term): its size is the mean relative deviation
// of B_i from (tr B_i / D) I, measured here on the same lattice, a = mean |B - tr B / D I| /
// (tr B / D). VISC-03's error must stay below 2 a: an absolute bound from the lattice's geometry.
// The uncorrected forms carry the first-order error sum V grad W . grad f, O(1) relative on this
// lattice: they are bounded from below so the test shows the lattice is disordered enough.
TEST(ViscValues, DisorderedLatticeAbsoluteBounds) {
  Lattice<2> L(30, 1.0, 5);
  const auto f = L.field([](const Vec2& x) { return std::pow(x[0], 4) + std::pow(x[1], 4); });
  auto exact = [](const Vec2& x) { return 12 * (x[0] * x[0] + x[1] * x[1]); };
  std::vector<Mat<2>> gamma(L.p.size());
  std::vector<double> trb(L.p.size());
  CorrectionMatrix<2> cm{L.p.V, gamma, trb};
  interact(L.nl, cm, L.sampled());
  double aniso = 0.0;
  int nf = 0;
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.fluid(i)) {
      const Mat<2> B = gamma[i].inverse();
      aniso += (B - 0.5 * trb[i] * Mat<2>::Identity()).norm() / (0.5 * trb[i]), ++nf;
    }
  aniso /= nf;
  std::map<ViscForm, double> err;
  for (const auto& name : visc_names()) {
    const ViscForm form = parse_visc(name);
    const auto lap = L.laplacian(form, f);
    double s = 0.0;
    for (std::size_t i = 0; i < L.p.size(); ++i)
      if (L.fluid(i) && exact(L.p.r[i]) > 1.0) // relative error away from the origin
        s += std::abs(lap[i] - exact(L.p.r[i])) / exact(L.p.r[i]);
    err[form] = s / nf;
  }
  EXPECT_LT(err[ViscForm::Visc03], 2.0 * aniso) << "anisotropy " << aniso;
  EXPECT_LT(err[ViscForm::Visc03], 0.15);
  EXPECT_GT(err[ViscForm::Visc01], 0.3);
  EXPECT_GT(err[ViscForm::Visc02], 0.3);
  EXPECT_GT(err[ViscForm::Visc04], 0.3);
  // VISC-03's tensor reading (visc03t) multiplies the scalar one by tr B tr Gamma / D^2 = 1 +
  // O(anisotropy^2), so the same geometric bound holds; its value is a band: measured 0.07358,
  // tolerance 5e-4, far above the build-to-build round-off of this deterministic mean (~1e-13)
  // and below the 9e-4 by which the scalar reading differs from it, so it tells the readings apart.
  EXPECT_LT(err[ViscForm::Visc03Tensor], 2.0 * aniso);
  EXPECT_NEAR(err[ViscForm::Visc03Tensor], 0.07358, 5e-4);
  for (auto [form, e] : err)
    std::printf("%s mean rel err %.5f (anisotropy %.4f)\n", visc_names()[int(form)].c_str(), e,
                aniso);
}

namespace {
// B_i = -sum_j V_j (W'/r) r_ij (x) r_ij over i's pairs, written here from the pairs (not through
// CorrectionMatrix): the second moment the braces of eq. (17) contract with H(u).
Mat<2> second_moment(const Lattice<2>& L, std::size_t i) {
  Mat<2> B = Mat<2>::Zero();
  for (auto q = L.nl.offset[i]; q < L.nl.offset[i + 1]; ++q) {
    const auto pr = L.nl.pair(q);
    B -= L.p.V[pr.j] * (pr.dW / pr.r) * pr.r_ij * pr.r_ij.transpose();
  }
  return B;
}
} // namespace

// The two readings of eq. (17)'s factor H_bb^{-1} / kappa (visc03.hpp) on the disordered lattice
// of seed 001, as exact discrete identities (eta = 0, round-off tolerance 1e-10 relative):
//  1. Given the exact gradient, the braces of eq. (17) for a quadratic u = (x - c)^T A (x - c) / 2
//     are exactly B_i : A (the first-order terms cancel pair by pair, there is no third-order
//     term), so the scalar reading gives D (B_i : A) / tr B_i and the tensor reading
//     tr(B_i^{-1}) (B_i : A) / D. Hence the scalar reading is exact for isotropic A on any lattice,
//     the tensor reading is not (its factor tr B tr B^{-1} / D^2 >= 1, equality iff B_i is
//     isotropic), and neither is exact for an anisotropic A.
//  2. Through the whole operator (corrected gradient included) both readings share the braces,
//     so visc03t_i / visc03_i = tr B_i tr Gamma_i / D^2 for any field.
TEST(ViscValues, Visc03ReadingsAreExactIdentitiesOfTheSecondMoment) {
  Lattice<2> L(20, 1.0, 7);
  const std::size_t N = L.p.size();
  std::vector<Mat<2>> gamma(N, Mat<2>::Identity());
  std::vector<double> trb(N, 2.0);
  for (std::size_t i = 0; i < N; ++i)
    if (L.fluid(i)) {
      const Mat<2> B = second_moment(L, i);
      gamma[i] = B.inverse(), trb[i] = B.trace();
    }
  const Vec2 c(0.3, 0.6);
  Mat<2> aniso;
  aniso << 3.0, -0.5, -0.5, 2.0;
  double tensor_iso_dev = 0.0, scalar_aniso_dev = 0.0;
  for (const Mat<2>& A : {Mat<2>(Mat<2>::Identity()), aniso}) {
    const auto u = L.field([&](const Vec2& x) { return 0.5 * (x - c).dot(A * (x - c)); });
    std::vector<Vec2> grad(N);
    for (std::size_t i = 0; i < N; ++i)
      grad[i] = A * (L.p.r[i] - c);
    for (Visc03Reading reading : {Visc03Reading::Scalar, Visc03Reading::Tensor}) {
      std::vector<double> out(N, 0.0);
      Visc03<2, double> op{L.p.V, u, grad, trb, gamma, reading, 0.0, out};
      interact(L.nl, op, L.sampled());
      for (std::size_t i = 0; i < N; ++i) {
        if (!L.fluid(i))
          continue;
        const Mat<2> B = gamma[i].inverse();
        const double BA = (B.array() * A.array()).sum();
        const double expected =
            reading == Visc03Reading::Scalar ? 2.0 * BA / trb[i] : gamma[i].trace() * BA / 2.0;
        ASSERT_NEAR(out[i], expected, 1e-10 * std::abs(expected)) << i;
        const double dev = std::abs(out[i] - A.trace()) / A.trace();
        if (A.isIdentity() && reading == Visc03Reading::Scalar)
          ASSERT_NEAR(out[i], 2.0, 1e-10) << i; // exact for x^2 + y^2
        if (A.isIdentity() && reading == Visc03Reading::Tensor)
          tensor_iso_dev = std::max(tensor_iso_dev, dev);
        if (!A.isIdentity() && reading == Visc03Reading::Scalar)
          scalar_aniso_dev = std::max(scalar_aniso_dev, dev);
      }
    }
  }
  // The identities above are not vacuous: this lattice makes B_i anisotropic enough that the
  // inexact cases miss by far more than round-off (printed).
  std::printf("tensor reading on x^2+y^2: max rel dev %.3g; scalar on anisotropic A: %.3g\n",
              tensor_iso_dev, scalar_aniso_dev);
  EXPECT_GT(tensor_iso_dev, 1e-3);
  EXPECT_GT(scalar_aniso_dev, 1e-3);

  // 2. The full operators (CorrectionMatrix and corrected gradient inside), any field.
  const auto f = L.field([](const Vec2& x) { return std::pow(x[0], 4) + std::pow(x[1], 4); });
  const auto s = L.laplacian(ViscForm::Visc03, f);
  const auto t = L.laplacian(ViscForm::Visc03Tensor, f);
  double max_ratio_dev = 0.0;
  for (std::size_t i = 0; i < N; ++i)
    if (L.fluid(i)) {
      const double ratio = trb[i] * gamma[i].trace() / 4.0;
      ASSERT_NEAR(t[i], ratio * s[i], 1e-10 * std::abs(t[i])) << i;
      max_ratio_dev = std::max(max_ratio_dev, ratio - 1.0);
    }
  EXPECT_GT(max_ratio_dev, 1e-3);
}

// ISPH's divergence (eq. 4, uncorrected) of a linear field u = A x + c on a perfect lattice is
// sum V (A r_ji) . grad W = tr A  S1 / D exactly (round-off tolerance); and the corrected pressure
// gradient of the projection (eqs. 10-11 with eq. 18) is exact for a linear pressure on a
// disordered lattice: u_new = u* - dt grad P / rho to round-off.
TEST(IsphOperators, DivergenceAndCorrectedProjectionOnLinearFields) {
  Lattice<2> L(16, 0.0, 1);
  Mat<2> A;
  A << 0.3, -1.2, 0.7, 0.5;
  std::vector<Vec2> u(L.p.size());
  for (std::size_t i = 0; i < u.size(); ++i)
    u[i] = A * L.p.r[i] + Vec2(1.0, -2.0);
  std::vector<double> div(L.p.size());
  isph_ops::Divergence<2> dv{L.p.V, u, div};
  interact(L.nl, dv, L.sampled());
  const double S1 = lattice_sums_2d(L.kernel, L.dx).S1;
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.fluid(i))
      ASSERT_NEAR(div[i], A.trace() * S1 / 2, 1e-11) << i;

  Lattice<2> M(16, 1.0, 11);
  std::vector<Mat<2>> gamma(M.p.size());
  std::vector<double> trb(M.p.size());
  CorrectionMatrix<2> cm{M.p.V, gamma, trb};
  interact(M.nl, cm, M.sampled());
  const Vec2 gp(2.0, -3.0);
  const double dt = 0.01;
  std::vector<double> P(M.p.size()), rho(M.p.size(), 2.0);
  std::vector<Vec2> us(M.p.size(), Vec2(0.5, 0.25)), un(M.p.size());
  for (std::size_t i = 0; i < P.size(); ++i)
    P[i] = 7.0 + gp.dot(M.p.r[i]);
  isph_ops::PressureCorrection<2> pc{M.p.V, P, rho, &gamma, us, dt, un};
  interact(M.nl, pc, M.sampled());
  const Vec2 expect = Vec2(0.5, 0.25) - dt / 2.0 * gp;
  for (std::size_t i = 0; i < M.p.size(); ++i)
    if (M.fluid(i))
      ASSERT_LT((un[i] - expect).norm(), 1e-12) << i;
}

// The PPE (eqs. 13-14) against a manufactured solution, through one step of the scheme on a
// periodic lattice: u* = grad phi, phi = eps sin(k x), alpha = 0, nu ~ 0, no shifting. The exact
// projection is P = rho phi / dt + const and u_new = 0. Discretely, with w_j = -2 V_j dW/r and
// m_p = sum_j w_j r_x^p on the perfect lattice, the Taylor expansions of the operators give
//   div u*  (eq. 4)  = 1/2 (phi'' m2 + phi'''' m4 / 6),
//   lap P   (eq. 14) = 1/2 (P''   m2 + P''''   m4 / 12),
//   grad P  (eq. 18) = P' (1 - k^2 m4 / (6 m2)),
// so the pressure amplitude is rho eps / dt (1 - e), e = k^2 m4 / (12 m2), and the corrected
// velocity u_new = 3 e grad phi, both to O(e^2) (e = 0.0066 here, e^2 < 5e-5). Tolerances: 5 % of
// e on the amplitude ratio (the O(e^2) and O(k^4 m6) terms, and eta^2 / r^2 < 2e-4 of eq. 14),
// 15 % of 3 e on |u_new| / |u*|. A wrong factor in the PPE matrix or source changes the amplitude
// by O(1).
TEST(IsphOperators, PpeManufacturedSolutionOnPeriodicLattice) {
  const int n = 40;
  const double dx = 1.0 / n, k = 2 * pi, eps = 0.01, dt = 1e-3;
  Particles<2> p;
  for_each_lattice_point<2>({0, 0}, {n, n}, dx, [&](const Vec2& x, const std::array<int, 2>&) {
    p.add(x, dx * dx, 1.0);
  });
  const int vw = p.add_vector("v_wall");
  std::vector<Vec2> x0(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.V[i] = dx * dx;
    p.v[i] = Vec2(eps * k * std::cos(k * p.r[i][0]), 0.0);
    x0[p.id[i]] = p.r[i];
  }
  Domain<2> box;
  box.periodic = {true, true};
  CubicSpline<2> W(1.2 * dx);
  IsphOptions opt;
  opt.solver = PpeSolverKind::Umfpack;
  opt.shifting = false;
  opt.alpha_ppe = 0.0;
  opt.wall_clearance = 0.0;
  Isph<2, CubicSpline<2>> s(p, box, W, opt, vw, 1e-12, dt, dx);
  s.step();
  // Moments of the perfect lattice.
  double m2 = 0, m4 = 0;
  const int nk = 4;
  for (int a = -nk; a <= nk; ++a)
    for (int b = -nk; b <= nk; ++b) {
      const double r = dx * std::hypot(a, b), rx2 = dx * dx * a * a;
      if (r == 0 || r >= W.support())
        continue;
      const double w = -2 * dx * dx * W.dW(r) / r;
      m2 += w * rx2, m4 += w * rx2 * rx2;
    }
  const double e = k * k * m4 / (12 * m2);
  // Least-squares fit P = A sin(k x0) + c over all particles (the lattice is periodic).
  double ss = 0, sp = 0, sum = 0, s2 = 0, ps = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double sn = std::sin(k * x0[p.id[i]][0]);
    ss += sn * sn, sp += sn * p.p[i], sum += sn, s2 += p.p[i];
  }
  const double N = static_cast<double>(p.size());
  const double Afit = (sp - sum * s2 / N) / (ss - sum * sum / N), c = (s2 - Afit * sum) / N;
  double resid = 0, umax = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    ps = Afit * std::sin(k * x0[p.id[i]][0]) + c;
    resid = std::max(resid, std::abs(p.p[i] - ps));
    umax = std::max(umax, p.v[i].norm());
  }
  const double amp = eps / dt; // rho = 1
  std::printf("e_pred %.5f  A/amp - 1 = %.5f  resid/amp %.2e  |u_new|/|u*| %.5f (pred %.5f)\n", e,
              Afit / amp - 1, resid / amp, umax / (eps * k), 3 * e);
  EXPECT_NEAR(Afit / amp, 1.0 - e, 0.05 * e);
  EXPECT_LT(resid, 1e-3 * amp); // the pressure is the single mode
  EXPECT_NEAR(umax / (eps * k), 3 * e, 0.15 * 3 * e);
}

// No-slip wall velocity (Adami et al. 2012, eqs. 22-23): u_w = 2 u_prescribed - sum_f u_f W_wf /
// sum_f W_wf over the fluid neighbours only. A wall row below a fluid with a linear velocity: the
// Shepard average is computed here from the kernel, so u_w is known to round-off.
TEST(WallVelocityValues, MirrorsTheShepardAverage) {
  Lattice<2> L(12, 0.0, 1);
  const Vec2 U(0.3, -0.1);
  std::vector<Vec2> vw(L.p.size(), Vec2::Zero()), v(L.p.size());
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    v[i] = Vec2(1.0 + 2.0 * L.p.r[i][1], 0.5 * L.p.r[i][0]);
    if (!L.fluid(i))
      vw[i] = U; // the padding acts as the wall, Buffer kind = not fluid
  }
  const std::vector<Vec2> v0 = v;
  WallVelocity<2> op{L.p.kind, vw, v};
  interact(L.nl, op, [&](std::size_t i) { return !L.fluid(i); });
  int checked = 0;
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    if (L.fluid(i))
      continue;
    Vec2 s = Vec2::Zero();
    double w = 0.0;
    for (auto q = L.nl.offset[i]; q < L.nl.offset[i + 1]; ++q)
      if (L.fluid(L.nl.j[q]))
        s += L.nl.W[q] * v0[L.nl.j[q]], w += L.nl.W[q];
    const Vec2 expect = w > 0 ? Vec2(2.0 * U - s / w) : U;
    ASSERT_LT((v[i] - expect).norm(), 1e-13) << i;
    checked += w > 0;
  }
  EXPECT_GT(checked, 40);
}

// The corrected gradient (eq. 18) of a Fourier mode f = sin(k x) on the perfect lattice: with
// w_j = -2 V_j dW / r and Gamma = (m2 / 2)^-1 I there, the odd terms of the Taylor expansion give
//   grad f . e_x = f' (1 - k^2 m4 / (6 m2)) + O(k^4 h^4),
// twice the relative error of the normalised Laplacian (the same moments, computed here over the
// particle's pairs). Tolerance 3 % of the predicted error plus 2e-4 (the next order), where
// |f'| > 0.5 k; the y component vanishes by symmetry.
TEST(CorrectedGradientValues, FourierModeMatchesTruncationError) {
  Lattice<2> L(20, 0.0, 1);
  const double k = 2 * pi;
  const auto f = L.field([&](const Vec2& x) { return std::sin(k * x[0]); });
  std::vector<Mat<2>> gamma(L.p.size());
  std::vector<double> trb(L.p.size());
  CorrectionMatrix<2> cm{L.p.V, gamma, trb};
  interact(L.nl, cm, L.sampled());
  std::vector<Vec2> g(L.p.size(), Vec2::Zero());
  CorrectedGradient<2, double> op{L.p.V, gamma, f, g};
  interact(L.nl, op, L.sampled());
  int checked = 0;
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    const double d = k * std::cos(k * L.p.r[i][0]);
    if (!L.fluid(i) || std::abs(d) < 0.5 * k)
      continue;
    double m2 = 0, m4 = 0;
    for (auto q = L.nl.offset[i]; q < L.nl.offset[i + 1]; ++q) {
      const auto pr = L.nl.pair(q);
      const double w = -2 * L.p.V[pr.j] * pr.dW / pr.r, rx2 = pr.r_ij[0] * pr.r_ij[0];
      m2 += w * rx2, m4 += w * rx2 * rx2;
    }
    const double e_pred = -k * k * m4 / (6 * m2), e = (g[i][0] - d) / d;
    ASSERT_NEAR(e, e_pred, 0.03 * std::abs(e_pred) + 2e-4) << i;
    ASSERT_NEAR(g[i][1], 0.0, 1e-10 * k) << i;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

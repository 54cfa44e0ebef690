// Operators of seed 001 on fields they must reproduce exactly:
//  - the corrected gradient (eq. 18-19) is exact for linear fields on a disordered lattice;
//  - VISC-03 and VISC-04 are exact for quadratic fields on a uniform lattice (eta = 0);
//  - VISC-03 and VISC-04 agree to round-off on a uniform lattice (section 4.4), eta > 0 too;
//  - VISC-03's tensor reading (visc03t) equals its scalar reading on a uniform lattice;
//  - a vector field's Laplacian is the Laplacian of each component;
//  - the patch_test case converges at second order for VISC-03/04 on a uniform lattice.
#include "cases/case.hpp"
#include "core/cell_list.hpp"
#include "core/kernels/kernel.hpp"
#include "core/lattice.hpp"
#include "operators/summation_density.hpp"
#include "operators/viscous_laplacian.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace sph;

namespace {

// A unit-box lattice of n^D sampled particles plus `pad` layers around, optionally disordered.
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
  auto sampled() const {
    return [this](std::size_t i) { return p.kind[i] == Kind::Fluid; };
  }
  template <class F>
  std::vector<double> field(F f) const {
    std::vector<double> out(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
      out[i] = f(p.r[i]);
    return out;
  }
  std::vector<double> laplacian(ViscForm form, const std::vector<double>& f, double eta) {
    ViscousLaplacian<D, double, CubicSpline<D>> lap(form, kernel, eta);
    std::vector<double> out(p.size(), 0.0);
    lap.prepare(nl, p.V, sampled());
    lap.apply(nl, p.V, f, out, sampled());
    return out;
  }
};

template <int D>
void corrected_gradient_is_exact_for_linear_fields() {
  Lattice<D> L(12, 1.0, 42);
  std::vector<Mat<D>> gamma(L.p.size());
  std::vector<double> trb(L.p.size());
  CorrectionMatrix<D> cm{L.p.V, gamma, trb};
  interact(L.nl, cm, L.sampled());
  Vec<D> a;
  for (int k = 0; k < D; ++k)
    a[k] = 0.7 - 1.3 * k;
  const auto f = L.field([&](const Vec<D>& x) { return 2.5 + a.dot(x); });
  std::vector<Vec<D>> g(L.p.size(), Vec<D>::Zero());
  CorrectedGradient<D, double> op{L.p.V, gamma, f, g};
  interact(L.nl, op, L.sampled());
  // The uncorrected gradient on the same particles is visibly wrong: the test can fail.
  double max_err = 0.0, max_plain = 0.0;
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    if (L.p.kind[i] != Kind::Fluid)
      continue;
    max_err = std::max(max_err, (g[i] - a).norm());
    Vec<D> plain = Vec<D>::Zero();
    for (auto k = L.nl.offset[i]; k < L.nl.offset[i + 1]; ++k) {
      const auto q = L.nl.pair(k);
      plain += L.p.V[q.j] * (f[q.j] - f[i]) * q.grad();
    }
    max_plain = std::max(max_plain, (plain - a).norm());
  }
  EXPECT_LT(max_err, 1e-11);
  EXPECT_GT(max_plain, 1e-3);
}

} // namespace

TEST(CorrectedGradient, ExactForLinearFieldsOnDisorderedLattice2D) {
  corrected_gradient_is_exact_for_linear_fields<2>();
}
TEST(CorrectedGradient, ExactForLinearFieldsOnDisorderedLattice3D) {
  corrected_gradient_is_exact_for_linear_fields<3>();
}

TEST(ViscousLaplacian, Visc03And04ExactForQuadraticsOnUniformLattice) {
  Lattice<2> L(16, 0.0, 1);
  const auto f =
      L.field([](const Vec2& x) { return 3 * x[0] * x[0] - x[0] * x[1] + 2 * x[1] * x[1] + x[0]; });
  const double exact = 2 * 3 + 2 * 2;
  for (ViscForm form : {ViscForm::Visc03, ViscForm::Visc04}) {
    const auto lap = L.laplacian(form, f, 0.0);
    for (std::size_t i = 0; i < L.p.size(); ++i)
      if (L.p.kind[i] == Kind::Fluid)
        ASSERT_NEAR(lap[i], exact, 1e-9 * exact) << "particle " << i;
  }
  // VISC-01 has no normalisation: it is not exact on the discrete lattice.
  const auto lap1 = L.laplacian(ViscForm::Visc01, f, 0.0);
  std::size_t i = 0;
  while (L.p.kind[i] != Kind::Fluid)
    ++i;
  EXPECT_GT(std::abs(lap1[i] - exact), 1e-6);
}

// Also VISC-03's two readings of H_bb^{-1} / kappa (visc03.hpp) agree on a uniform lattice: B_i
// is isotropic there by the lattice's symmetry, so tr Gamma_i / D = D / tr B_i up to the round-off
// of the pair sums (tolerance 1e-12 relative), with and without eta. On a disordered lattice they
// differ by tr B tr Gamma / D^2 (test_operator_values.cpp).
TEST(ViscousLaplacian, Visc03EqualsVisc04OnUniformLattice) {
  for (double eta : {0.0, 0.1}) {
    Lattice<2> L(20, 0.0, 1);
    const auto f = L.field([](const Vec2& x) { return std::pow(x[0], 4) + std::pow(x[1], 4); });
    const auto a = L.laplacian(ViscForm::Visc03, f, eta * L.kernel.h);
    const auto b = L.laplacian(ViscForm::Visc04, f, eta * L.kernel.h);
    const auto t = L.laplacian(ViscForm::Visc03Tensor, f, eta * L.kernel.h);
    for (std::size_t i = 0; i < L.p.size(); ++i)
      if (L.p.kind[i] == Kind::Fluid) {
        ASSERT_NEAR(a[i], b[i], 1e-10 * std::abs(b[i]) + 1e-12);
        ASSERT_NEAR(t[i], a[i], 1e-12 * std::abs(a[i]) + 1e-14) << i;
      }
  }
  // ... and they differ on a disordered lattice.
  Lattice<2> L(20, 1.0, 3);
  const auto f = L.field([](const Vec2& x) { return std::pow(x[0], 4) + std::pow(x[1], 4); });
  const auto a = L.laplacian(ViscForm::Visc03, f, 0.0);
  const auto b = L.laplacian(ViscForm::Visc04, f, 0.0);
  double diff = 0.0;
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.p.kind[i] == Kind::Fluid)
      diff = std::max(diff, std::abs(a[i] - b[i]));
  EXPECT_GT(diff, 1e-3);
}

TEST(ViscousLaplacian, VectorFieldIsComponentwise) {
  Lattice<2> L(12, 1.0, 9);
  std::vector<Vec2> u(L.p.size());
  std::vector<double> ux(L.p.size()), uy(L.p.size());
  for (std::size_t i = 0; i < L.p.size(); ++i) {
    const Vec2 x = L.p.r[i];
    u[i] = Vec2(std::sin(3 * x[0]) * x[1], x[0] * x[0] * x[1]);
    ux[i] = u[i][0], uy[i] = u[i][1];
  }
  for (const auto& name : visc_names()) {
    const ViscForm form = parse_visc(name);
    ViscousLaplacian<2, Vec2, CubicSpline<2>> lap(form, L.kernel, 0.01 * L.kernel.h);
    std::vector<Vec2> out(L.p.size(), Vec2::Zero());
    lap.prepare(L.nl, L.p.V, L.sampled());
    lap.apply(L.nl, L.p.V, u, out, L.sampled());
    const auto lx = L.laplacian(form, ux, 0.01 * L.kernel.h);
    const auto ly = L.laplacian(form, uy, 0.01 * L.kernel.h);
    for (std::size_t i = 0; i < L.p.size(); ++i)
      if (L.p.kind[i] == Kind::Fluid) {
        ASSERT_NEAR(out[i][0], lx[i], 1e-10 * (1 + std::abs(lx[i]))) << name;
        ASSERT_NEAR(out[i][1], ly[i], 1e-10 * (1 + std::abs(ly[i]))) << name;
      }
  }
}

TEST(SummationDensity, UniformLatticeGivesReferenceDensity) {
  Lattice<2> L(20, 0.0, 1, 1.3);
  SummationDensity<2, CubicSpline<2>> op{L.p, L.kernel};
  interact(L.nl, op, L.sampled());
  for (std::size_t i = 0; i < L.p.size(); ++i)
    if (L.p.kind[i] == Kind::Fluid) {
      EXPECT_NEAR(L.p.rho[i], 1.0, 2e-3); // mass dx^2, reference density 1
      EXPECT_NEAR(L.p.V[i], L.dx * L.dx / L.p.rho[i] * 1.0, 1e-15);
    }
}

namespace {
double patch_metric(const std::string& visc, int n, const std::string& lattice,
                    const std::string& metric = "err") {
  const CaseInfo* c = find_case("patch_test");
  Params prm;
  for (const auto& s : c->params)
    prm[s.name] = s.default_value;
  prm["visc"] = visc, prm["n_side"] = std::int64_t{n}, prm["lattice"] = lattice;
  RunResult r = c->run(prm, RunContext{});
  for (const auto& [k, v] : r.metrics)
    if (k == metric)
      return v;
  ADD_FAILURE() << "no metric " << metric;
  return 0.0;
}
} // namespace

// The L2 error falls as dx^2. The mean relative error of eq. (21) falls as dx^2 log(1/dx): its
// denominator lap f = 12 (x^2 + y^2) vanishes at the corner, so its observed order is lower.
TEST(PatchTest, Visc03And04ConvergeSecondOrderOnUniformLattice) {
  for (const char* v : {"visc03", "visc04"}) {
    const double e20 = patch_metric(v, 20, "uniform", "err_l2");
    const double e40 = patch_metric(v, 40, "uniform", "err_l2");
    EXPECT_GT(std::log2(e20 / e40), 1.95) << v << " " << e20 << " " << e40;
    EXPECT_GT(std::log2(patch_metric(v, 20, "uniform") / patch_metric(v, 40, "uniform")), 1.6);
  }
}

TEST(PatchTest, Visc03IsMostAccurateOnDisorderedLattice) {
  const double e3 = patch_metric("visc03", 30, "disordered");
  for (const char* v : {"visc01", "visc02", "visc04"})
    EXPECT_LT(e3, patch_metric(v, 30, "disordered")) << v;
}

// err_r2_max, the maximum relative error on f = x^2 + y^2 (lap = 4). On the uniform lattice the
// normalised forms are exact for quadratics except for eta: each pair weight carries r^2 / (r^2 +
// eta^2), so the relative error is a weighted mean of eta^2 / (r^2 + eta^2) < (eta / dx)^2 =
// (eta / h)^2 (h / dx)^2 = 1.4e-8 at the case's defaults (measured 1.03e-8). On the disordered
// lattice VISC-03's scalar reading is still exact for x^2 + y^2 given the exact gradient
// (test_operator_values.cpp), so its error there is that of the corrected gradient on a quadratic,
// O(h), times sum_j V_j grad W_ij, O(1 / h): O(1) and not converging; both readings stay far from
// exact (printed).
TEST(PatchTest, IsotropicQuadraticErrorIsEtaOnUniformAndGradientOnDisorderedLattice) {
  double h_over_dx = 0.0, eta_over_h = 0.0; // the case's defaults, which patch_metric runs
  for (const auto& s : find_case("patch_test")->params) {
    if (s.name == "h_over_dx")
      h_over_dx = std::get<double>(s.default_value);
    if (s.name == "eta_over_h")
      eta_over_h = std::get<double>(s.default_value);
  }
  const double bound = std::pow(eta_over_h * h_over_dx, 2);
  for (const char* v : {"visc03", "visc03t", "visc04"})
    EXPECT_LT(patch_metric(v, 20, "uniform", "err_r2_max"), bound) << v;
  for (const char* v : {"visc03", "visc03t"}) {
    const double e = patch_metric(v, 20, "disordered", "err_r2_max");
    std::printf("%s err_r2_max on the disordered 20x20 lattice: %.3f\n", v, e);
    EXPECT_GT(e, 0.05) << v;
  }
}

// Particles of an axisymmetric duct along x (pipes, cones, sudden steps): the fluid lumen and its
// wall, on body-fitted rings so that every cross-section's area is the lumen's exactly (a Cartesian
// lattice in a round pipe is a staircase whose area is off by 2-8 % at 7-16 particles across).
//
// Geometry: the wall line in the meridian plane (x, rho), rho = sqrt(y^2 + z^2), a polyline
// (x_k, R_k) with x non-decreasing; a vertical segment (two vertices at one x) is a sudden step.
// The lumen is rho < R(x). Distances to the wall are those in the meridian plane, which for a
// surface of revolution are the 3D distances.
//
// Particles: slices x_s = x_lo + (s + 1/2) dx. In a slice, the lumen holds n_r = max(1,
// round(R(x_s) / dx)) rings of radial spacing dr = R(x_s) / n_r at rho_k = (k + 1/2) dr, the wall
// rings continue outward from R(x_s) at spacing dx, kept where their distance to the wall line is
// below the wall thickness (one kernel support: the dummy-particle layers) and outside the lumen.
// A ring of radius rho holds n = max(1, round(2 pi rho / dx)) particles at angles (j + o) 2 pi / n,
// o = 1/2 on odd rings (no radial spokes); each particle's volume is its share of the ring's
// annulus times dx: V = dx pi ((rho + dr/2)^2 - (rho - dr/2)^2) / n, so that the volumes of a
// slice's lumen add up to pi R(x_s)^2 dx exactly.
#pragma once

#include "core/vec.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace sph {

class AxisymmetricDuct {
public:
  // Wall vertices in the meridian plane; throws unless x is non-decreasing and R > 0.
  AxisymmetricDuct(std::vector<double> x, std::vector<double> R)
      : x_(std::move(x)), R_(std::move(R)) {
    if (x_.size() < 2 || x_.size() != R_.size())
      throw std::invalid_argument("AxisymmetricDuct: needs at least two (x, R) vertices");
    for (std::size_t k = 0; k < x_.size(); ++k) {
      if (!(R_[k] > 0.0))
        throw std::invalid_argument("AxisymmetricDuct: the radii must be positive");
      if (k > 0 && x_[k] < x_[k - 1])
        throw std::invalid_argument("AxisymmetricDuct: the x of the vertices must not decrease");
    }
  }

  // The lumen radius at x (x clamped to the polyline's ends; on a step the larger side: x at the
  // step belongs to the segment that starts there).
  double radius(double x) const {
    if (x <= x_.front())
      return R_.front();
    for (std::size_t k = 0; k + 1 < x_.size(); ++k)
      if (x < x_[k + 1] && x_[k + 1] > x_[k])
        return R_[k] + (R_[k + 1] - R_[k]) * (x - x_[k]) / (x_[k + 1] - x_[k]);
    return R_.back();
  }
  bool in_lumen(double x, double rho) const { return rho < radius(x); }

  // The point of the wall line nearest to (x, rho) in the meridian plane (the line extended as
  // straight pipes beyond its ends), and its distance.
  struct WallPoint {
    double x, rho, d;
  };
  WallPoint nearest_wall_point(double x, double rho) const {
    WallPoint best{x, rho, std::numeric_limits<double>::infinity()};
    auto seg = [&](double x0, double r0, double x1, double r1) {
      const double ex = x1 - x0, er = r1 - r0, L2 = ex * ex + er * er;
      const double t =
          L2 > 0.0 ? std::clamp(((x - x0) * ex + (rho - r0) * er) / L2, 0.0, 1.0) : 0.0;
      const double xp = x0 + t * ex, rp = r0 + t * er, d = std::hypot(x - xp, rho - rp);
      if (d < best.d)
        best = {xp, rp, d};
    };
    const double far = 1e6 * (x_.back() - x_.front() + R_.front() + R_.back());
    seg(x_.front() - far, R_.front(), x_.front(), R_.front());
    for (std::size_t k = 0; k + 1 < x_.size(); ++k)
      seg(x_[k], R_[k], x_[k + 1], R_[k + 1]);
    seg(x_.back(), R_.back(), x_.back() + far, R_.back());
    return best;
  }
  double distance_to_wall(double x, double rho) const { return nearest_wall_point(x, rho).d; }

  // The unit normal of the wall at a wall particle r (outside the lumen), pointing into the
  // fluid: from r towards the nearest point of the wall line, in r's meridian plane (radially
  // inward on a pipe, along the axis on a step's face; from the corner where the wall wraps
  // around a corner of the fluid, as at a step face's outer edge).
  Vec3 wall_normal(const Vec3& r) const {
    const double rho = std::hypot(r.y(), r.z());
    const WallPoint w = nearest_wall_point(r.x(), rho);
    if (!(w.d > 0.0))
      throw std::invalid_argument("AxisymmetricDuct::wall_normal: the point is on the wall line");
    const Vec3 e_rho = rho > 0.0 ? Vec3(0.0, r.y() / rho, r.z() / rho) : Vec3(0.0, 1.0, 0.0);
    return (w.x - r.x()) / w.d * Vec3(1.0, 0.0, 0.0) + (w.rho - rho) / w.d * e_rho;
  }

  struct Point {
    Vec3 r;
    double V;   // volume (particle mass rho0 V)
    bool fluid; // in the lumen (else wall)
  };

  // The particles of slices x in [x_lo, x_lo + n_slices dx): lumen rings and wall rings thinner
  // than `thickness`. Ordered by slice, then radius, then angle.
  std::vector<Point> particles(double x_lo, int n_slices, double dx, double thickness) const {
    std::vector<Point> out;
    const double R_max = *std::max_element(R_.begin(), R_.end());
    for (int s = 0; s < n_slices; ++s) {
      const double xs = x_lo + (s + 0.5) * dx, R = radius(xs);
      const int n_r = ring_count(R, dx);
      const auto lumen = section(xs, dx);
      out.insert(out.end(), lumen.begin(), lumen.end());
      for (int k = 0;; ++k) {
        const double rho = R + (k + 0.5) * dx;
        if (rho > R_max + thickness + dx)
          break;
        if (in_lumen(xs, rho) || distance_to_wall(xs, rho) >= thickness)
          continue;
        ring(out, xs, rho, dx, dx, n_r + k, false);
      }
    }
    return out;
  }

  // The transverse pattern of a slice at x (the rings of its lumen, as particles() places them)
  // with their volumes per unit slice thickness dx: an inflow emitter's rows.
  std::vector<Point> section(double x, double dx) const {
    std::vector<Point> out;
    const double R = radius(x);
    const int n_r = ring_count(R, dx);
    const double dr = R / n_r;
    for (int k = 0; k < n_r; ++k)
      ring(out, x, (k + 0.5) * dr, dr, dx, k, true);
    return out;
  }
  // The radial spacing of the lumen's rings in the slice at x.
  double ring_spacing(double x, double dx) const {
    const double R = radius(x);
    return R / ring_count(R, dx);
  }

private:
  std::vector<double> x_, R_;

  // Rings of the lumen of radius R: round(R / dx), at least one.
  static int ring_count(double R, double dx) {
    return std::max(1, static_cast<int>(std::lround(R / dx)));
  }

  static void ring(std::vector<Point>& out, double xs, double rho, double dr, double dx, int k,
                   bool fluid) {
    const double pi = std::numbers::pi;
    const int n = std::max(1, static_cast<int>(std::lround(2.0 * pi * rho / dx)));
    const double annulus = pi * (std::pow(rho + 0.5 * dr, 2) - std::pow(rho - 0.5 * dr, 2));
    const double o = (k % 2) ? 0.5 : 0.0;
    for (int j = 0; j < n; ++j) {
      const double phi = (j + o) * 2.0 * pi / n;
      out.push_back({Vec3(xs, rho * std::cos(phi), rho * std::sin(phi)), dx * annulus / n, fluid});
    }
  }
};

} // namespace sph

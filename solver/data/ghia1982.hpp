// Reference centreline velocities of the lid-driven square cavity at Re = 1000 from
//   U. Ghia, K. N. Ghia, C. T. Shin, "High-Re solutions for incompressible flow using the
//   Navier-Stokes equations and a multigrid method", J. Comput. Phys. 48 (1982) 387-411,
//   Table I (u along the vertical centreline x = 0.5) and Table II (v along the horizontal
//   centreline y = 0.5), columns Re = 1000 and Re = 100, the 17 points of the original tables.
// Transcription cross-checked against independent public copies (Re = 1000: pysph's
// ghia_cavity_data.py, Oceananigans.jl validation, NATriuM CompareToGhia.cpp; Re = 100: pysph's
// ghia_cavity_data.py). The point coordinates are the same for every Re.
//
// Used ONLY to compute error metrics of a run (diagnostics/cavity_profiles.hpp); never a result.
#pragma once

#include <array>

namespace sph::data {

inline constexpr int ghia_points = 17;

// Table I: y and u(x = 0.5, y) at Re = 1000 (U0 = 1, L = 1).
inline constexpr std::array<double, ghia_points> ghia_re1000_y{
    1.0000, 0.9766, 0.9688, 0.9609, 0.9531, 0.8516, 0.7344, 0.6172, 0.5000,
    0.4531, 0.2813, 0.1719, 0.1016, 0.0703, 0.0625, 0.0547, 0.0000};
inline constexpr std::array<double, ghia_points> ghia_re1000_u{
    1.00000,  0.65928,  0.57492,  0.51117,  0.46604,  0.33304,  0.18719,  0.05702, -0.06080,
    -0.10648, -0.27805, -0.38289, -0.29730, -0.22220, -0.20196, -0.18109, 0.00000};

// Table II: x and v(x, y = 0.5) at Re = 1000.
inline constexpr std::array<double, ghia_points> ghia_re1000_x{
    1.0000, 0.9688, 0.9609, 0.9531, 0.9453, 0.9063, 0.8594, 0.8047, 0.5000,
    0.2344, 0.2266, 0.1563, 0.0938, 0.0781, 0.0703, 0.0625, 0.0000};
inline constexpr std::array<double, ghia_points> ghia_re1000_v{
    0.00000, -0.21388, -0.27669, -0.33714, -0.39188, -0.51550, -0.42665, -0.31966, 0.02526,
    0.32235, 0.33075,  0.37095,  0.32627,  0.30353,  0.29012,  0.27485,  0.00000};

// Minimum of u along x = 0.5 among Ghia's 17 points (y = 0.1719): the "experimental" u_x,min
// of seed 001 section 5.1 (Err = |u_x,min,n - u_x,min,e|).
inline constexpr double ghia_re1000_u_min = -0.38289;

// Table I, column Re = 100: u(x = 0.5, y) at ghia_re1000_y.
inline constexpr std::array<double, ghia_points> ghia_re100_u{
    1.00000,  0.84123,  0.78871,  0.73722,  0.68717,  0.23151,  0.00332,  -0.13641, -0.20581,
    -0.21090, -0.15662, -0.10150, -0.06434, -0.04775, -0.04192, -0.03717, 0.00000};
// Table II, column Re = 100: v(x, y = 0.5) at ghia_re1000_x.
inline constexpr std::array<double, ghia_points> ghia_re100_v{
    0.00000, -0.05906, -0.07391, -0.08864, -0.10313, -0.16914, -0.22445, -0.24533, 0.05454,
    0.17527, 0.17507,  0.16077,  0.12317,  0.10890,  0.10091,  0.09233,  0.00000};
// Minimum of u among the 17 points at Re = 100 (y = 0.4531).
inline constexpr double ghia_re100_u_min = -0.21090;

// The table of one Reynolds number (nullptr members when Ghia has no column for it here).
struct GhiaTable {
  const std::array<double, ghia_points>* u = nullptr; // at ghia_re1000_y
  const std::array<double, ghia_points>* v = nullptr; // at ghia_re1000_x
  double u_min = 0.0;
};
// Ghia's columns this project carries: Re = 100 and Re = 1000 (exact match of Re).
inline GhiaTable ghia_table(double Re) {
  if (Re == 1000.0)
    return {&ghia_re1000_u, &ghia_re1000_v, ghia_re1000_u_min};
  if (Re == 100.0)
    return {&ghia_re100_u, &ghia_re100_v, ghia_re100_u_min};
  return {};
}

} // namespace sph::data

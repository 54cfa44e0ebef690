// Small fixed-size vectors and matrices of the solver, dimension as a template parameter.
// Every per-particle vector field is std::vector<Vec<D>> (one array per field: structure of
// arrays); never hand-indexed flat storage.
#pragma once

#include <Eigen/Dense>

namespace sph {

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

template <int D>
using Mat = Eigen::Matrix<double, D, D>;

using Vec2 = Vec<2>;
using Vec3 = Vec<3>;

} // namespace sph

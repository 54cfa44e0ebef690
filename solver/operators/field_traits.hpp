// Operators act on scalar fields (double) and vector fields (Vec<D>) alike. Grad<D, T> is the
// gradient's type: Vec<D> for a scalar field, Mat<D> (rows: component, columns: derivative
// direction, G(a, b) = d u_a / d x_b) for a vector field.
#pragma once

#include "core/vec.hpp"

namespace sph {

template <class T>
T zero() {
  if constexpr (std::is_arithmetic_v<T>)
    return T(0);
  else
    return T::Zero();
}

template <int D, class T>
struct GradType;
template <int D>
struct GradType<D, double> {
  using type = Vec<D>;
};
template <int D>
struct GradType<D, Vec<D>> {
  using type = Mat<D>;
};
template <int D, class T>
using Grad = typename GradType<D, T>::type;

// (f_j - f_i) (x) g: the gradient contribution of one pair, g a vector.
template <int D>
Vec<D> outer(double df, const Vec<D>& g) {
  return df * g;
}
template <int D>
Mat<D> outer(const Vec<D>& du, const Vec<D>& g) {
  return du * g.transpose();
}

// grad f . s: directional derivative along s.
template <int D>
double along(const Vec<D>& grad, const Vec<D>& s) {
  return grad.dot(s);
}
template <int D>
Vec<D> along(const Mat<D>& grad, const Vec<D>& s) {
  return grad * s;
}

} // namespace sph

#pragma once
// Elementwise ops. Binary ops broadcast NumPy-style (shapes aligned at the trailing
// dimension; a dimension of size 1 stretches). All ops are differentiable and recorded on
// the tape when an input requires gradients. Both inputs must have the same dtype.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

Tensor add(const Tensor& a, const Tensor& b);
Tensor sub(const Tensor& a, const Tensor& b);
Tensor mul(const Tensor& a, const Tensor& b);
Tensor div(const Tensor& a, const Tensor& b);
/// Elementwise maximum / minimum; the gradient goes to the larger (smaller) input, to `a`
/// on ties.
Tensor maximum(const Tensor& a, const Tensor& b);
Tensor minimum(const Tensor& a, const Tensor& b);

Tensor neg(const Tensor& x);
Tensor exp(const Tensor& x);
Tensor log(const Tensor& x);
Tensor sqrt(const Tensor& x);
Tensor square(const Tensor& x);
Tensor abs(const Tensor& x);
Tensor relu(const Tensor& x);
Tensor elu(const Tensor& x, double alpha = 1.0);
/// Finite for |x| up to 1e30 and beyond (no exp of a large positive argument).
Tensor sigmoid(const Tensor& x);
Tensor tanh(const Tensor& x);
/// log(1 + exp(x)) in the overflow-free form max(x, 0) + log1p(exp(-|x|)).
Tensor softplus(const Tensor& x);
Tensor addScalar(const Tensor& x, double value);
Tensor mulScalar(const Tensor& x, double value);
Tensor powScalar(const Tensor& x, double exponent);
Tensor clamp(const Tensor& x, double low, double high);

/// Sums `x` down to `shape` (the reverse of broadcasting `shape` up to x's shape).
Tensor sumToShape(const Tensor& x, const Shape& shape);
/// The broadcast result shape of a and b; throws naming `op` and both shapes if incompatible.
Shape broadcastShapes(const Shape& a, const Shape& b, const char* op);

inline Tensor operator+(const Tensor& a, const Tensor& b) {
  return add(a, b);
}
inline Tensor operator-(const Tensor& a, const Tensor& b) {
  return sub(a, b);
}
inline Tensor operator*(const Tensor& a, const Tensor& b) {
  return mul(a, b);
}
inline Tensor operator/(const Tensor& a, const Tensor& b) {
  return div(a, b);
}
inline Tensor operator-(const Tensor& a) {
  return neg(a);
}
inline Tensor operator+(const Tensor& a, double s) {
  return addScalar(a, s);
}
inline Tensor operator-(const Tensor& a, double s) {
  return addScalar(a, -s);
}
inline Tensor operator*(const Tensor& a, double s) {
  return mulScalar(a, s);
}
inline Tensor operator*(double s, const Tensor& a) {
  return mulScalar(a, s);
}

} // namespace simpli::ocl

#pragma once
// Tensor: a contiguous device buffer with a shape (0..6 dimensions, row-major) and a dtype
// (float32 for work, float64 for reference runs of the same kernels). Copies share the
// buffer (like a handle); ops return new tensors. Autograd: a tensor that requires gradients
// records, for every op that consumes it, a node on the tape (see autograd.h).
#include "simpli/ocl/dtype.h"

#include <CL/cl.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace simpli::ocl {

using Shape = std::vector<int64_t>;
constexpr int kMaxDims = 6;

std::string toString(const Shape& shape);
int64_t numelOf(const Shape& shape);

class Buffer;
struct Node;
struct TensorImpl;

class Tensor {
public:
  Tensor() = default;

  // ---- creation -------------------------------------------------------------------------
  /// Uninitialised contents.
  static Tensor empty(const Shape& shape, Dtype dtype = Dtype::F32);
  static Tensor full(const Shape& shape, double value, Dtype dtype = Dtype::F32);
  static Tensor zeros(const Shape& shape, Dtype dtype = Dtype::F32) {
    return full(shape, 0.0, dtype);
  }
  static Tensor ones(const Shape& shape, Dtype dtype = Dtype::F32) {
    return full(shape, 1.0, dtype);
  }
  static Tensor fromHost(const std::vector<float>& values, const Shape& shape,
                         Dtype dtype = Dtype::F32);
  static Tensor fromHost(const std::vector<double>& values, const Shape& shape,
                         Dtype dtype = Dtype::F64);
  /// Uniform in [low, high), reproducible for a seed on every device and in both precisions
  /// (counter-based generator: element i depends only on (seed, i)).
  static Tensor uniform(const Shape& shape, double low, double high, uint64_t seed,
                        Dtype dtype = Dtype::F32);
  /// Normal(mean, std), reproducible as uniform().
  static Tensor normal(const Shape& shape, double mean, double stddev, uint64_t seed,
                       Dtype dtype = Dtype::F32);
  /// Evenly spaced values start, start+step, ... (numel = n).
  static Tensor arange(int64_t n, double start = 0.0, double step = 1.0, Dtype dtype = Dtype::F32);

  // ---- properties -----------------------------------------------------------------------
  bool defined() const { return impl_ != nullptr; }
  const Shape& shape() const;
  int64_t size(int axis) const; ///< negative axes count from the end
  int dim() const { return static_cast<int>(shape().size()); }
  int64_t numel() const;
  Dtype dtype() const;
  std::size_t bytes() const { return static_cast<std::size_t>(numel()) * sizeOf(dtype()); }
  cl_mem buffer() const;
  std::string describe() const; ///< "f32[2, 3]"

  // ---- host transfer --------------------------------------------------------------------
  std::vector<double> toVector() const;   ///< blocking download, converted to double
  std::vector<float> toVectorF32() const; ///< blocking download, converted to float
  double item() const;                    ///< the value of a one-element tensor
  void copyFromHost(const std::vector<double>& values);
  /// Writes `value` into every element (in place; not recorded on the tape).
  void fill(double value);
  /// A tensor of the other dtype with the same values (recorded on the tape).
  Tensor to(Dtype dtype) const;
  /// A copy with its own buffer (recorded on the tape).
  Tensor clone() const;
  /// this += other (same shape and dtype; in place, not recorded).
  void addInPlace(const Tensor& other);
  /// this *= factor (in place, not recorded).
  void mulInPlace(double factor);

  // ---- autograd -------------------------------------------------------------------------
  bool requiresGrad() const;
  /// Marks a leaf as a parameter whose gradient is accumulated by backward().
  Tensor& setRequiresGrad(bool value = true);
  /// The accumulated gradient of a leaf (undefined before the first backward()).
  Tensor grad() const;
  void setGrad(const Tensor& grad);
  void zeroGrad();
  /// Back-propagates from this scalar (one element) tensor; gradients accumulate into leaves.
  void backward() const;
  /// Back-propagates `gradOutput` (same shape as this tensor).
  void backward(const Tensor& gradOutput) const;
  /// The same buffer, cut from the tape.
  Tensor detach() const;
  /// True when this tensor was produced by a recorded op.
  bool hasGradFn() const;

  // ---- internals used by ops ------------------------------------------------------------
  explicit Tensor(std::shared_ptr<TensorImpl> impl) : impl_(std::move(impl)) {}
  const std::shared_ptr<TensorImpl>& impl() const { return impl_; }
  /// The same buffer with another shape of equal numel (no copy, not recorded).
  Tensor viewAs(const Shape& shape) const;

private:
  std::shared_ptr<TensorImpl> impl_;
};

struct TensorImpl {
  std::shared_ptr<Buffer> buffer;
  Shape shape;
  Dtype dtype = Dtype::F32;
  bool requiresGrad = false;
  std::shared_ptr<Node> gradFn; ///< the op that produced this tensor (null for leaves)
  std::shared_ptr<TensorImpl> grad;
};

} // namespace simpli::ocl

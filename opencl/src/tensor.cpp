#include "simpli/ocl/tensor.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"

#include <sstream>

namespace simpli::ocl {

std::string toString(const Shape& shape) {
  std::ostringstream os;
  os << '[';
  for (std::size_t i = 0; i < shape.size(); ++i)
    os << (i ? ", " : "") << shape[i];
  os << ']';
  return os.str();
}

int64_t numelOf(const Shape& shape) {
  int64_t n = 1;
  for (auto s : shape)
    n *= s;
  return n;
}

namespace {

const char* const kEmptyMessage = "operation on an undefined (default-constructed) tensor";

void validateShape(const Shape& shape, const char* what) {
  if (shape.size() > static_cast<std::size_t>(kMaxDims))
    fail(what, ": shape ", toString(shape), " has more than ", kMaxDims, " dimensions");
  for (auto s : shape)
    if (s < 0)
      fail(what, ": shape ", toString(shape), " has a negative dimension");
  checkedInt(numelOf(shape), what);
}

} // namespace

Tensor Tensor::empty(const Shape& shape, Dtype dtype) {
  validateShape(shape, "Tensor::empty");
  auto impl = std::make_shared<TensorImpl>();
  impl->shape = shape;
  impl->dtype = dtype;
  impl->buffer =
      Device::current().pool().acquire(static_cast<std::size_t>(numelOf(shape)) * sizeOf(dtype));
  return Tensor(impl);
}

Tensor Tensor::full(const Shape& shape, double value, Dtype dtype) {
  Tensor t = empty(shape, dtype);
  t.fill(value);
  return t;
}

Tensor Tensor::fromHost(const std::vector<float>& values, const Shape& shape, Dtype dtype) {
  return fromHost(std::vector<double>(values.begin(), values.end()), shape, dtype);
}

Tensor Tensor::fromHost(const std::vector<double>& values, const Shape& shape, Dtype dtype) {
  validateShape(shape, "Tensor::fromHost");
  if (static_cast<int64_t>(values.size()) != numelOf(shape))
    fail("Tensor::fromHost: ", values.size(), " values for shape ", toString(shape), " (",
         numelOf(shape), " elements)");
  Tensor t = empty(shape, dtype);
  t.copyFromHost(values);
  return t;
}

Tensor Tensor::uniform(const Shape& shape, double low, double high, uint64_t seed, Dtype dtype) {
  Tensor t = empty(shape, dtype);
  Launch("elementwise", "random_uniform", dtype)
      .arg(static_cast<int>(t.numel()))
      .arg(seed)
      .real(low)
      .real(high)
      .arg(t)
      .run(t.numel());
  return t;
}

Tensor Tensor::normal(const Shape& shape, double mean, double stddev, uint64_t seed, Dtype dtype) {
  Tensor t = empty(shape, dtype);
  Launch("elementwise", "random_normal", dtype)
      .arg(static_cast<int>(t.numel()))
      .arg(seed)
      .real(mean)
      .real(stddev)
      .arg(t)
      .run(t.numel());
  return t;
}

Tensor Tensor::arange(int64_t n, double start, double step, Dtype dtype) {
  Tensor t = empty({n}, dtype);
  Launch("elementwise", "arange", dtype)
      .arg(static_cast<int>(n))
      .real(start)
      .real(step)
      .arg(t)
      .run(n);
  return t;
}

const Shape& Tensor::shape() const {
  if (!impl_)
    fail(kEmptyMessage);
  return impl_->shape;
}

int64_t Tensor::size(int axis) const {
  const int n = dim();
  const int a = axis < 0 ? axis + n : axis;
  if (a < 0 || a >= n)
    fail("Tensor::size: axis ", axis, " out of range for shape ", toString(shape()));
  return shape()[a];
}

int64_t Tensor::numel() const {
  return numelOf(shape());
}

Dtype Tensor::dtype() const {
  if (!impl_)
    fail(kEmptyMessage);
  return impl_->dtype;
}

cl_mem Tensor::buffer() const {
  if (!impl_)
    fail(kEmptyMessage);
  return impl_->buffer->mem();
}

std::string Tensor::describe() const {
  if (!impl_)
    return "undefined";
  return toString(dtype()) + toString(shape());
}

std::vector<double> Tensor::toVector() const {
  const auto n = static_cast<std::size_t>(numel());
  std::vector<double> out(n);
  if (n == 0)
    return out;
  auto queue = Device::current().queue();
  if (dtype() == Dtype::F64) {
    checkCl(
        clEnqueueReadBuffer(queue, buffer(), CL_TRUE, 0, n * 8, out.data(), 0, nullptr, nullptr),
        "Tensor::toVector");
  } else {
    std::vector<float> tmp(n);
    checkCl(
        clEnqueueReadBuffer(queue, buffer(), CL_TRUE, 0, n * 4, tmp.data(), 0, nullptr, nullptr),
        "Tensor::toVector");
    out.assign(tmp.begin(), tmp.end());
  }
  return out;
}

std::vector<float> Tensor::toVectorF32() const {
  auto v = toVector();
  return std::vector<float>(v.begin(), v.end());
}

double Tensor::item() const {
  if (numel() != 1)
    fail("Tensor::item: tensor ", describe(), " does not have exactly one element");
  return toVector()[0];
}

void Tensor::copyFromHost(const std::vector<double>& values) {
  const auto n = static_cast<std::size_t>(numel());
  if (values.size() != n)
    fail("Tensor::copyFromHost: ", values.size(), " values for tensor ", describe());
  if (n == 0)
    return;
  auto queue = Device::current().queue();
  if (dtype() == Dtype::F64) {
    checkCl(clEnqueueWriteBuffer(queue, buffer(), CL_TRUE, 0, n * 8, values.data(), 0, nullptr,
                                 nullptr),
            "Tensor::copyFromHost");
  } else {
    std::vector<float> tmp(values.begin(), values.end());
    checkCl(
        clEnqueueWriteBuffer(queue, buffer(), CL_TRUE, 0, n * 4, tmp.data(), 0, nullptr, nullptr),
        "Tensor::copyFromHost");
  }
}

void Tensor::fill(double value) {
  Launch("elementwise", "fill", dtype())
      .arg(static_cast<int>(numel()))
      .real(value)
      .arg(*this)
      .run(numel());
}

Tensor Tensor::to(Dtype target) const {
  if (target == dtype())
    return *this;
  Tensor out = empty(shape(), target);
  const int n = static_cast<int>(numel());
  if (target == Dtype::F64)
    Launch("elementwise", "convert_from_f32", Dtype::F64).arg(n).arg(*this).arg(out).run(n);
  else
    Launch("elementwise", "convert_to_f32", Dtype::F64).arg(n).arg(*this).arg(out).run(n);
  const Dtype source = dtype();
  return record("to", out, {*this},
                [source](const Tensor& g) { return std::vector<Tensor>{g.to(source)}; });
}

Tensor Tensor::clone() const {
  Tensor out = empty(shape(), dtype());
  if (bytes() > 0)
    checkCl(clEnqueueCopyBuffer(Device::current().queue(), buffer(), out.buffer(), 0, 0, bytes(), 0,
                                nullptr, nullptr),
            "Tensor::clone");
  return record("clone", out, {*this}, [](const Tensor& g) { return std::vector<Tensor>{g}; });
}

bool Tensor::requiresGrad() const {
  return impl_ && impl_->requiresGrad;
}

Tensor& Tensor::setRequiresGrad(bool value) {
  if (!impl_)
    fail(kEmptyMessage);
  if (impl_->gradFn)
    fail("setRequiresGrad: tensor ", describe(),
         " is the result of an op; only leaves (parameters, inputs) can be marked");
  impl_->requiresGrad = value;
  return *this;
}

Tensor Tensor::grad() const {
  return impl_ && impl_->grad ? Tensor(impl_->grad) : Tensor();
}

void Tensor::setGrad(const Tensor& grad) {
  if (grad.defined() && grad.shape() != shape())
    fail("setGrad: gradient ", grad.describe(), " does not match tensor ", describe());
  impl_->grad = grad.impl();
}

void Tensor::zeroGrad() {
  if (impl_ && impl_->grad)
    Tensor(impl_->grad).fill(0.0);
}

Tensor Tensor::detach() const {
  auto impl = std::make_shared<TensorImpl>();
  impl->buffer = this->impl_ ? impl_->buffer : nullptr;
  impl->shape = shape();
  impl->dtype = dtype();
  return Tensor(impl);
}

bool Tensor::hasGradFn() const {
  return impl_ && impl_->gradFn;
}

Tensor Tensor::viewAs(const Shape& newShape) const {
  validateShape(newShape, "viewAs");
  if (numelOf(newShape) != numel())
    fail("viewAs: cannot view ", describe(), " as ", toString(newShape));
  auto impl = std::make_shared<TensorImpl>();
  impl->buffer = impl_->buffer;
  impl->shape = newShape;
  impl->dtype = dtype();
  return Tensor(impl);
}

} // namespace simpli::ocl

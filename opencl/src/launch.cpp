#include "simpli/ocl/launch.h"

#include "simpli/error.h"
#include "simpli/ocl/profiler.h"

#include <limits>

namespace simpli::ocl {

Launch::Launch(const char* program, const char* kernel, Dtype dtype, const std::string& options)
    : kernel_(Device::current().programs().kernel(program, kernel, dtype, options)), dtype_(dtype),
      name_(std::string(program) + "." + kernel) {}

Launch& Launch::arg(const Tensor& tensor) {
  return arg(tensor.buffer());
}

Launch& Launch::arg(cl_mem mem) {
  checkCl(clSetKernelArg(kernel_, index_++, sizeof(cl_mem), &mem), name_.c_str());
  return *this;
}

Launch& Launch::arg(int value) {
  cl_int v = value;
  checkCl(clSetKernelArg(kernel_, index_++, sizeof(cl_int), &v), name_.c_str());
  return *this;
}

Launch& Launch::arg(uint64_t value) {
  cl_ulong v = value;
  checkCl(clSetKernelArg(kernel_, index_++, sizeof(cl_ulong), &v), name_.c_str());
  return *this;
}

Launch& Launch::arg(const cl_int8& value) {
  checkCl(clSetKernelArg(kernel_, index_++, sizeof(cl_int8), &value), name_.c_str());
  return *this;
}

Launch& Launch::real(double value) {
  if (dtype_ == Dtype::F64) {
    cl_double v = value;
    checkCl(clSetKernelArg(kernel_, index_++, sizeof(v), &v), name_.c_str());
  } else {
    cl_float v = static_cast<float>(value);
    checkCl(clSetKernelArg(kernel_, index_++, sizeof(v), &v), name_.c_str());
  }
  return *this;
}

Launch& Launch::local(std::size_t bytes) {
  checkCl(clSetKernelArg(kernel_, index_++, bytes, nullptr), name_.c_str());
  return *this;
}

namespace {
std::size_t roundUp(int64_t n, std::size_t multiple) {
  const auto v = static_cast<std::size_t>(n < 1 ? 1 : n);
  return (v + multiple - 1) / multiple * multiple;
}
} // namespace

void Launch::run(int64_t n) {
  if (n <= 0)
    return;
  const std::size_t local = 64;
  const std::size_t global = roundUp(n, local);
  enqueue(1, &global, &local);
}

void Launch::run2(int64_t n0, int64_t n1, std::size_t l0, std::size_t l1) {
  if (n0 <= 0 || n1 <= 0)
    return;
  const std::size_t global[2] = {roundUp(n0, l0), roundUp(n1, l1)};
  const std::size_t local[2] = {l0, l1};
  enqueue(2, global, local);
}

void Launch::run3(int64_t n0, int64_t n1, int64_t n2, std::size_t l0, std::size_t l1,
                  std::size_t l2) {
  if (n0 <= 0 || n1 <= 0 || n2 <= 0)
    return;
  const std::size_t global[3] = {roundUp(n0, l0), roundUp(n1, l1), roundUp(n2, l2)};
  const std::size_t local[3] = {l0, l1, l2};
  enqueue(3, global, local);
}

void Launch::enqueue(cl_uint dims, const std::size_t* global, const std::size_t* local) {
  const Profiler::Scope profile(Profiler::enabled() ? name_ : std::string());
  Device& device = Device::current();
  cl_int status = clEnqueueNDRangeKernel(device.queue(), kernel_, dims, nullptr, global, local, 0,
                                         nullptr, nullptr);
  checkCl(status, name_.c_str());
  device.settleFirstLaunch(kernel_, dims, global, local);
}

cl_int8 toInt8(const Shape& values) {
  cl_int8 out;
  for (int i = 0; i < 8; ++i)
    out.s[i] = i < static_cast<int>(values.size()) ? static_cast<cl_int>(values[i]) : 0;
  return out;
}

Shape stridesOf(const Shape& shape) {
  Shape strides(shape.size(), 1);
  for (int d = static_cast<int>(shape.size()) - 2; d >= 0; --d)
    strides[d] = strides[d + 1] * shape[d + 1];
  return strides;
}

int checkedInt(int64_t n, const char* op) {
  if (n > std::numeric_limits<int>::max())
    fail(op, ": ", n, " elements exceed the kernels' 32-bit index range");
  return static_cast<int>(n);
}

} // namespace simpli::ocl

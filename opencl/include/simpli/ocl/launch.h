#pragma once
// Sets kernel arguments and enqueue a kernel on the current device.
// Work-group sizes are fixed (PoCL compiles one specialisation per local size, so letting the
// runtime choose per global size would recompile kernels all the time); global sizes are
// rounded up and kernels bounds-check their ids.
#include "simpli/ocl/device.h"
#include "simpli/ocl/program_cache.h"
#include "simpli/ocl/tensor.h"

#include <CL/cl.h>

#include <array>
#include <cstdint>
#include <string>

namespace simpli::ocl {

class Launch {
public:
  Launch(const char* program, const char* kernel, Dtype dtype, const std::string& options = "");

  Launch& arg(const Tensor& tensor);
  Launch& arg(cl_mem mem);
  Launch& arg(int value);
  Launch& arg(uint64_t value);
  Launch& arg(const cl_int8& value);
  /// A floating-point scalar in the kernel's precision (float or double).
  Launch& real(double value);
  /// A __local buffer of `bytes` bytes.
  Launch& local(std::size_t bytes);

  /// 1-D launch over n items (local size 64).
  void run(int64_t n);
  /// 2-D / 3-D launch with explicit local size; global sizes are rounded up to it.
  void run2(int64_t n0, int64_t n1, std::size_t l0 = 16, std::size_t l1 = 4);
  void run3(int64_t n0, int64_t n1, int64_t n2, std::size_t l0 = 16, std::size_t l1 = 4,
            std::size_t l2 = 1);

private:
  void enqueue(cl_uint dims, const std::size_t* global, const std::size_t* local);
  cl_kernel kernel_;
  Dtype dtype_;
  std::string name_;
  cl_uint index_ = 0;
};

/// Shape and row-major strides as OpenCL int8 (unused dims: shape 1, stride 0).
cl_int8 toInt8(const Shape& values);
Shape stridesOf(const Shape& shape);
/// Checks that n fits the kernels' 32-bit indices.
int checkedInt(int64_t n, const char* op);

} // namespace simpli::ocl

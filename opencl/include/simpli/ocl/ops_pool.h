#pragma once
// 2-D pooling over the last two dimensions of x ([N, C, H, W], or any rank >= 2: leading
// dimensions are independent planes). No padding; floor mode: the output has
// (H - kernel) / stride + 1 rows, and input rows past the last window are ignored.
#include "simpli/ocl/tensor.h"

namespace simpli::ocl {

/// Maximum over each window. The gradient goes to the window's maximum; on ties to the first
/// one in row-major order (NaN propagates, as in PyTorch).
Tensor maxPool2d(const Tensor& x, int kernel, int stride);
Tensor maxPool2d(const Tensor& x, int kernelH, int kernelW, int strideH, int strideW);

/// Mean over each window.
Tensor avgPool2d(const Tensor& x, int kernel, int stride);
Tensor avgPool2d(const Tensor& x, int kernelH, int kernelW, int strideH, int strideW);

} // namespace simpli::ocl

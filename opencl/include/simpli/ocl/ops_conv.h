#pragma once
// 2-D and 3-D convolutions (cross-correlation, as in PyTorch), differentiable in the input, the
// weight and the bias. Lowered to GEMMs through CLBlast: an im2col kernel (which also applies the
// padding) builds column blocks of at most a few tens of MB, so large volumes never materialise
// a full column matrix. 1x1 convolutions with stride 1 and no padding skip im2col. Small
// convolutions (few channels, x stride 1) take a direct path instead: kernels that read the
// input taps themselves (conv_direct.cl), chosen per pass (forward, input gradient, weight
// gradient) by a rule on the shape in ops_conv.cpp.
#include "simpli/ocl/tensor.h"

#include <array>
#include <cstddef>

namespace simpli::ocl {

enum class PaddingMode {
  Zeros,    ///< samples outside the input are 0
  Replicate ///< samples outside the input repeat the nearest edge sample
};

/// x [N, C, H, W], weight [O, C, kh, kw], bias [O] or undefined -> [N, O, Ho, Wo] with
/// Ho = (H + 2 * padding[0] - kh) / stride[0] + 1 (likewise Wo). Throws simpli::Error naming
/// the op and the shapes on rank, channel or dtype mismatch, non-positive stride, negative
/// padding, or a kernel larger than the padded input.
Tensor conv2d(const Tensor& x, const Tensor& weight, const Tensor& bias, std::array<int, 2> stride,
              std::array<int, 2> padding, PaddingMode mode = PaddingMode::Zeros);
/// The same stride and padding along both axes.
Tensor conv2d(const Tensor& x, const Tensor& weight, const Tensor& bias = Tensor(), int stride = 1,
              int padding = 0, PaddingMode mode = PaddingMode::Zeros);

/// x [N, C, D, H, W], weight [O, C, kd, kh, kw], bias [O] or undefined -> [N, O, Do, Ho, Wo];
/// stride and padding per axis (D, H, W); replicate padding applies along D as well.
Tensor conv3d(const Tensor& x, const Tensor& weight, const Tensor& bias, std::array<int, 3> stride,
              std::array<int, 3> padding, PaddingMode mode = PaddingMode::Zeros);
/// The same stride and padding along all three axes.
Tensor conv3d(const Tensor& x, const Tensor& weight, const Tensor& bias = Tensor(), int stride = 1,
              int padding = 0, PaddingMode mode = PaddingMode::Zeros);

/// Upper bound, in bytes, of the column block im2col builds per batch item (default 32 MiB;
/// at least one output row is always taken). Smaller saves device memory, larger gives fewer
/// and bigger GEMMs. Returns the previous value.
std::size_t setConvColumnBudget(std::size_t bytes);

/// Which kernels compute the passes of convolutions other than 1x1.
enum class ConvPath {
  Auto,    ///< direct for the small shapes where it measured faster, else lowered (default)
  Lowered, ///< im2col + GEMM / GEMM + col2im (environment SIMPLI_CONV_DIRECT=0)
  Direct   ///< always direct (environment SIMPLI_CONV_DIRECT=1)
};
/// Sets the path (the start value comes from SIMPLI_CONV_DIRECT); returns the previous one.
ConvPath setConvPath(ConvPath path);

} // namespace simpli::ocl

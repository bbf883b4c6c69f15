#pragma once
// Resampling with PyTorch semantics (align_corners = False throughout, no antialiasing).
//
// Resize: output sample p of an axis with `in` input and `out` output samples reads around the
// source position s = (p + 0.5) * in / out - 0.5 (computed exactly in integers).
//  * bilinear = nn.Upsample / F.interpolate(mode='bilinear'): s is clamped at 0, taps
//    floor(s) and min(floor(s) + 1, in - 1), weights 1 - t and t (t = s - floor(s));
//  * bicubic = F.interpolate(mode='bicubic'): Keys cubic with A = -0.75, taps
//    floor(s) - 1 .. floor(s) + 2 clamped to the border (e.g. scale 0.5 gives the weights
//    -0.09375, 0.59375, 0.59375, -0.09375).
// Both resize the last two dimensions of x [..., H, W] (rank >= 2), up or down, and are
// differentiable with respect to x.
//
// Grid sampling = F.grid_sample(input, grid) with its defaults: bilinear, zero padding,
// align_corners = False. A grid value g maps to the source pixel coordinate
// ((g + 1) * size - 1) / 2, so g = -1 and +1 are the outer edges of the border pixels; taps
// outside the image contribute 0 (values fade to 0 across the half-pixel border band).
#include "simpli/ocl/tensor.h"

#include <cstdint>

namespace simpli::ocl {

Tensor resizeBilinear(const Tensor& x, int64_t outH, int64_t outW);
Tensor resizeBicubic(const Tensor& x, int64_t outH, int64_t outW);

/// input [N, C, H, W], grid [N, Ho, Wo, 2] holding (x, y) in [-1, 1] -> [N, C, Ho, Wo].
/// Differentiable with respect to the input and the grid (float64 gradients to the input need
/// the device extension cl_khr_int64_base_atomics).
Tensor gridSample(const Tensor& input, const Tensor& grid);

/// Validity of each sample point of grid [N, Ho, Wo, 2]: [N, 1, Ho, Wo] holding 1 where
/// |x| <= 1 and |y| <= 1 (inclusive), else 0 (also for NaN). Not differentiable (no tape).
Tensor gridSampleMask(const Tensor& grid);

} // namespace simpli::ocl

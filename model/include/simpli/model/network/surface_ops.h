#pragma once
// Parameter-free steps of the SIMPLI network between its modules (spec §3, §4.5,
// §4.9). All are differentiable and run in the dtype of their input.
#include "simpli/ocl/tensor.h"

#include <vector>

namespace simpli::network {

/// The level-0 aggregation state (§3 step 5): PE_C of the plane index p = 0..P-1,
/// [P, channels] (identical for every pixel).
ocl::Tensor planeState(int planes, int channels, ocl::Dtype dtype);

/// The reference's level-0 quirk (§3 step 8): tanh, then clamp to [-1, 1], on ALL channels of
/// the last `count` planes (the nearest ones) of features [B, P, ...]; the other planes are
/// returned unchanged. count = 0 returns the input.
ocl::Tensor nearPlanesTanh(const ocl::Tensor& features, int count);

/// fMPI0 (§3 steps 7-9): cat([nearPlanesTanh(features, tanhPlanes), sigmoid(alphaLogits)],
/// axis 2) with features [B, P, C, h, w] (the raw aggregator output) and alphaLogits
/// [B, P, 1, h, w] (the alpha decoder applied to the raw features) -> [B, P, C + 1, h, w].
ocl::Tensor assembleMpi0(const ocl::Tensor& features, const ocl::Tensor& alphaLogits,
                         int tanhPlanes);

/// The RGBA decoders' squashing (§4.4): tanh then clamp to [-1, 1] on channels 0-2 and sigmoid
/// on channel 3 of axis `channelAxis` (which must have size 4).
ocl::Tensor activateRgba(const ocl::Tensor& raw, int channelAxis);

/// Layer depths from group opacities (§4.9). logits [B, L * G, H, W] with G = ceil(P / L)
/// (layer-major: channel k * G + g), planeDepths the P plane depths (index 0 = farthest).
/// Group k covers planes k * s + g (s = floor(P / L)); alpha_{k,g} = sigmoid(logit), with
/// alpha_{k,0} := 1; D_k = d_{k,G-1} + sum_g alpha_g T_g (d_{k,g} - d_{k,G-1}) with
/// T_g = prod_{g' > g} (1 - alpha_{g'} + 1e-6). Returns [B, L, H, W] (layer 0 = farthest).
ocl::Tensor processDepth(const ocl::Tensor& logits, const std::vector<double>& planeDepths,
                         int layers);

} // namespace simpli::network

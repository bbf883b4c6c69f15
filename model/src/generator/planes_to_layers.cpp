// Step 5 of the generator (spec §3, §4.8, §4.9): the 41 corrected planes are
// pooled into L layers by anchored ray attention, per-layer group opacities give the layer
// depths (at h1 x w1 for the level-2 discrepancy mesh, and from bicubic-upsampled logits at
// full resolution for the final, frozen depth), and the first RGBA decoder gives RGBA1.
//
// MPI-only configs (the DeepView-like baseline) skip the pooling: the surfaces are the P planes
// themselves, each at its constant plane depth.
#include "generator/internal.h"

#include "simpli/model/network/surface_ops.h"

#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_resample.h"
#include "simpli/ocl/ops_shape.h"

namespace simpli::generator {

namespace {

using ocl::Tensor;

/// [P, h, w] with plane p at its depth everywhere.
Tensor constantPlaneDepths(const std::vector<double>& depths, int h, int w, ocl::Dtype dtype) {
  const int P = static_cast<int>(depths.size());
  return ocl::expand(ocl::reshape(Tensor::fromHost(depths, {P}, dtype), {P, 1, 1}), {P, h, w});
}

} // namespace

Level1Surfaces planesToLayers(const Context& ctx, const MpiLevels& mpi) {
  const network::SimpliNetwork& net = ctx.net;
  const network::NetworkConfig& cfg = net.config();
  const ocl::Dtype dtype = net.parameters().dtype();
  const int P = cfg.numPlanes;
  const int64_t Cs = mpi.fmpi1.size(1), h1 = ctx.h1, w1 = ctx.w1;
  Level1Surfaces out;

  if (cfg.mpiOnly) {
    out.features = mpi.fmpi1;
    out.mesh.depth = constantPlaneDepths(ctx.planeDepths, ctx.h1, ctx.w1, dtype);
    out.finalDepth = constantPlaneDepths(ctx.planeDepths, ctx.h2, ctx.w2, dtype);
  } else {
    const int L = cfg.numLayers;
    // Positions = normalised disparity (1/d - 1/far) / (1/near - 1/far) = p / (P - 1).
    std::vector<double> positions(static_cast<std::size_t>(P));
    const double far = ctx.planeDepths.front(), near = ctx.planeDepths.back();
    for (int p = 0; p < P; ++p)
      positions[p] =
          P == 1 ? 0.0 : (1.0 / ctx.planeDepths[p] - 1.0 / far) / (1.0 / near - 1.0 / far);
    const Tensor layers = net.planesDeformer->forward(ocl::reshape(mpi.fmpi1, {1, P, Cs, h1, w1}),
                                                      Tensor::fromHost(positions, {P}, dtype));
    ctx.hook("planes_deformer_lvl1.out", layers); // [1, L, Cs, h1, w1]
    out.features = ocl::reshape(layers, {L, Cs, h1, w1});

    // Group-opacity logits [L, G, h1, w1], layer-major as the reference's [1, L*G, h1, w1].
    const Tensor logits = net.depthDecoder->forward(out.features);
    ctx.hook("depth_decoder_lvl1.out", logits);
    const int64_t G = logits.size(1);
    const Tensor flat = ocl::reshape(logits, {1, L * G, h1, w1});
    const Tensor d1 = network::processDepth(flat, ctx.planeDepths, L); // [1, L, h1, w1]
    ctx.hook("process_depth_lvl1.out", d1);
    out.mesh.depth = ocl::reshape(d1, {L, h1, w1});
    // The final depth re-decodes the bicubic-upsampled logits (not the depths), §3 step 6.4.
    const Tensor up =
        (ctx.h2 == h1 && ctx.w2 == w1) ? flat : ocl::resizeBicubic(flat, ctx.h2, ctx.w2);
    ctx.hook("process_depth_lvl2.in0", up);
    const Tensor d = network::processDepth(up, ctx.planeDepths, L); // [1, L, h2, w2]
    ctx.hook("layered_depth", d);
    out.finalDepth = ocl::reshape(d, {L, ctx.h2, ctx.w2});
  }

  const Tensor raw = net.rgbaDecoders[0].forward(out.features); // [S, 4, h1, w1]
  ctx.hook("rgba_decoder_lvl1.out", raw);
  out.mesh.rgba = network::activateRgba(raw, 1);
  ctx.clock->mark(cfg.mpiOnly ? "mpi_surfaces" : "planes_to_layers");
  return out;
}

} // namespace simpli::generator

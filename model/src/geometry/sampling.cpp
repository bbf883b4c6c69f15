#include "geometry/sampling.h"

#include "model_kernels.h"
#include "simpli/error.h"

#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

#include <cmath>
#include <string>

namespace simpli::geometry {

using ocl::Launch;
using ocl::Shape;
using ocl::Tensor;

namespace {

// Views handled by the fused kernels' private arrays: compiled for the smallest power of two
// that holds V (few specialisations, little private memory for the usual 2-8 views).
constexpr int kMaxViews = 64;

std::string maxViewsOption(int views) {
  int n = 4;
  while (n < views)
    n *= 2;
  return "-DMAX_VIEWS=" + std::to_string(n);
}

// Geometry of one launch, shared by forward and backward closures.
struct Dims {
  int S, h, w, V, C, Hs, Ws;
  int layers;     // 1: corner grid + per-pixel depth
  int perSurface; // sources [V, S, C, Hs, Ws]
  double rfx, rfy, rcx, rcy;
};

// The leading arguments every sweep.cl kernel takes: sizes, corner grid, depth map.
Launch& addCommon(Launch& l, const Dims& d) {
  return l.arg(d.S).arg(d.h).arg(d.w).arg(d.V).arg(d.C).arg(d.Hs).arg(d.Ws).arg(d.layers).arg(
      d.layers);
}

void checkSpec(const SurfaceSpec& spec) {
  const char* op = spec.op;
  if (spec.surfaces < 1)
    fail(op, ": need at least one surface (got ", spec.surfaces, ")");
  if (spec.height < 1 || spec.width < 1)
    fail(op, ": output grid ", spec.height, "x", spec.width, " must be at least 1x1");
  if (spec.layers && (spec.height < 2 || spec.width < 2))
    fail(op, ": depth ", spec.depth.describe(),
         " needs at least 2x2 texels (the corner grid u = j / (W - 1) is undefined for 1)");
}

// Validates maps (and optional weight maps) against the views and the spec; returns the dims.
Dims checkInputs(const Tensor& sources, const Tensor& weights, const scene::Camera& reference,
                 const std::vector<scene::Camera>& views, const SurfaceSpec& spec,
                 bool allowPerSurface) {
  const char* op = spec.op;
  checkSpec(spec);
  if (!sources.defined())
    fail(op, ": undefined source maps");
  if (views.empty())
    fail(op, ": no source cameras (sources ", sources.describe(), ")");
  checkCamera(reference, op, "reference camera");
  for (std::size_t v = 0; v < views.size(); ++v)
    checkCamera(views[v], op, "source camera " + std::to_string(v));
  const bool perSurface = sources.dim() == 5;
  if (sources.dim() != 4 && !(allowPerSurface && perSurface))
    fail(op, ": sources ", sources.describe(),
         allowPerSurface ? " must be [V, C, Hs, Ws] or [V, S, C, Hs, Ws]"
                         : " must be [V, C, Hs, Ws]");
  const Shape& s = sources.shape();
  if (s[0] != static_cast<int64_t>(views.size()))
    fail(op, ": sources ", sources.describe(), " hold ", s[0], " views but ", views.size(),
         " source cameras were given");
  if (perSurface && s[1] != spec.surfaces)
    fail(op, ": per-surface sources ", sources.describe(), " hold ", s[1], " surfaces, expected ",
         spec.surfaces);
  if (sources.numel() == 0)
    fail(op, ": sources ", sources.describe(), " are empty");
  if (spec.depth.dtype() != sources.dtype())
    fail(op, ": dtype mismatch, sources ", sources.describe(), " vs depth ", spec.depth.describe());
  Dims d{};
  d.S = spec.surfaces;
  d.h = spec.height;
  d.w = spec.width;
  d.V = static_cast<int>(views.size());
  d.C = static_cast<int>(s[s.size() - 3]);
  d.Hs = static_cast<int>(s[s.size() - 2]);
  d.Ws = static_cast<int>(s[s.size() - 1]);
  d.layers = spec.layers ? 1 : 0;
  d.perSurface = perSurface ? 1 : 0;
  d.rfx = reference.fx;
  d.rfy = reference.fy;
  d.rcx = reference.cx;
  d.rcy = reference.cy;
  if (weights.defined()) {
    const Shape expected{s[0], spec.surfaces, 1, s[2], s[3]};
    if (weights.shape() != expected)
      fail(op, ": weights ", weights.describe(),
           " must be [V, S, 1, Hs, Ws] = ", ocl::toString(expected), " for sources ",
           sources.describe());
    if (weights.dtype() != sources.dtype())
      fail(op, ": dtype mismatch, sources ", sources.describe(), " vs weights ",
           weights.describe());
  }
  // 32-bit indices in the kernels.
  ocl::checkedInt(sources.numel(), op);
  const int64_t pixels = int64_t{d.S} * d.h * d.w;
  ocl::checkedInt(pixels * d.V * d.C, op); // plain samples [V, S, C, h, w]
  ocl::checkedInt(pixels * 2 * d.C, op);   // mean | variance [S, 2C, h, w]
  if (weights.defined())
    ocl::checkedInt(weights.numel(), op);
  return d;
}

Tensor upload(const std::vector<double>& values, ocl::Dtype dtype) {
  return Tensor::fromHost(values, {static_cast<int64_t>(values.size())}, dtype);
}

} // namespace

void checkCamera(const scene::Camera& c, const char* op, const std::string& role) {
  if (!c.R.allFinite() || !c.t.allFinite())
    fail(op, ": ", role, " has a non-finite pose (R = [", c.R.row(0), "; ", c.R.row(1), "; ",
         c.R.row(2), "], t = [", c.t.transpose(), "])");
  const double values[4] = {c.fx, c.fy, c.cx, c.cy};
  const char* names[4] = {"fx", "fy", "cx", "cy"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(values[i]))
      fail(op, ": ", role, " has relative intrinsic ", names[i], " = ", values[i]);
  if (c.fx == 0 || c.fy == 0)
    fail(op, ": ", role, " has a zero focal length (relative fx = ", c.fx, ", fy = ", c.fy, ")");
}

std::vector<double> viewBlocks(const scene::Camera& reference,
                               const std::vector<scene::Camera>& views) {
  std::vector<double> blocks;
  blocks.reserve(16 * views.size());
  for (const scene::Camera& v : views) {
    const Eigen::Matrix3d R = v.R * reference.R.transpose();
    const Eigen::Vector3d t = v.t - R * reference.t;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        blocks.push_back(R(i, j));
    blocks.insert(blocks.end(), {t.x(), t.y(), t.z(), v.fx, v.fy, v.cx, v.cy});
  }
  return blocks;
}

SurfaceSamples sampleSurfaces(const Tensor& sources, const scene::Camera& reference,
                              const std::vector<scene::Camera>& views, const SurfaceSpec& spec) {
  const Dims d = checkInputs(sources, Tensor(), reference, views, spec, true);
  ensureModelKernels();
  const ocl::Dtype dtype = sources.dtype();
  const Tensor cams = upload(viewBlocks(reference, views), dtype);
  Tensor out = Tensor::empty({d.V, d.S, d.C, d.h, d.w}, dtype);
  Tensor mask = Tensor::empty({d.V, d.S, 1, d.h, d.w}, dtype);
  Launch l("sweep", "sweep_forward", dtype);
  addCommon(l, d)
      .arg(d.perSurface)
      .arg(cams)
      .real(d.rfx)
      .real(d.rfy)
      .real(d.rcx)
      .real(d.rcy)
      .arg(spec.depth)
      .arg(sources)
      .arg(out)
      .arg(mask)
      .run3(d.w, d.h, d.S);
  const Tensor& depth = spec.depth;
  const bool wantSrc = sources.requiresGrad();
  const bool wantDepth = spec.layers && depth.requiresGrad();
  out = ocl::record(
      spec.op, out, {sources, depth},
      [d, wantSrc, wantDepth, cams, src = sources.detach(), dep = depth.detach()](const Tensor& g) {
        Tensor gsrc = wantSrc ? Tensor::zeros(src.shape(), g.dtype()) : Tensor();
        Tensor gdep = wantDepth ? Tensor::empty(dep.shape(), g.dtype()) : Tensor();
        Launch l("sweep", "sweep_backward", g.dtype());
        addCommon(l, d)
            .arg(d.perSurface)
            .arg(cams)
            .real(d.rfx)
            .real(d.rfy)
            .real(d.rcx)
            .real(d.rcy)
            .arg(dep)
            .arg(src)
            .arg(g)
            .arg(wantSrc ? 1 : 0)
            .arg(wantSrc ? gsrc : g) // unused placeholder when not wanted
            .arg(wantDepth ? 1 : 0)
            .arg(wantDepth ? gdep : g)
            .run3(d.w, d.h, d.S);
        return std::vector<Tensor>{gsrc, gdep};
      });
  return {out, mask};
}

Tensor sampleSurfacesCoverage(const Tensor& sources, const scene::Camera& reference,
                              const std::vector<scene::Camera>& views, const SurfaceSpec& spec) {
  const Dims d = checkInputs(sources, Tensor(), reference, views, spec, false);
  ensureModelKernels();
  const ocl::Dtype dtype = sources.dtype();
  Tensor out = Tensor::empty({d.S, 1, d.h, d.w}, dtype);
  Launch l("sweep", "sweep_coverage", dtype);
  addCommon(l, d)
      .arg(upload(viewBlocks(reference, views), dtype))
      .real(d.rfx)
      .real(d.rfy)
      .real(d.rcx)
      .real(d.rcy)
      .arg(spec.depth)
      .arg(out)
      .run3(d.w, d.h, d.S);
  return out;
}

Tensor sampleSurfacesMeanVar(const Tensor& sources, const Tensor& weights,
                             const scene::Camera& reference,
                             const std::vector<scene::Camera>& views, const SurfaceSpec& spec) {
  const Dims d = checkInputs(sources, weights, reference, views, spec, false);
  if (d.V > kMaxViews)
    fail(spec.op, ": ", d.V, " source views (sources ", sources.describe(),
         "); the fused aggregation handles at most ", kMaxViews);
  ensureModelKernels();
  const ocl::Dtype dtype = sources.dtype();
  const std::string options = maxViewsOption(d.V);
  const Tensor cams = upload(viewBlocks(reference, views), dtype);
  const bool hasWeights = weights.defined();
  Tensor out = Tensor::empty({d.S, 2 * d.C, d.h, d.w}, dtype);
  Launch l("sweep", "sweep_meanvar_forward", dtype, options);
  addCommon(l, d)
      .arg(cams)
      .real(d.rfx)
      .real(d.rfy)
      .real(d.rcx)
      .real(d.rcy)
      .arg(spec.depth)
      .arg(sources)
      .arg(hasWeights ? 1 : 0)
      .arg(hasWeights ? weights : sources) // unused placeholder without weights
      .arg(out)
      .run3(d.w, d.h, d.S);
  const Tensor& depth = spec.depth;
  const bool wantSrc = sources.requiresGrad();
  const bool wantWeights = hasWeights && weights.requiresGrad();
  const bool wantDepth = spec.layers && depth.requiresGrad();
  return ocl::record(spec.op, out, {sources, weights, depth},
                     [d, options, hasWeights, wantSrc, wantWeights, wantDepth, cams,
                      src = sources.detach(), wts = weights.defined() ? weights.detach() : Tensor(),
                      dep = depth.detach()](const Tensor& g) {
                       Tensor gsrc = wantSrc ? Tensor::zeros(src.shape(), g.dtype()) : Tensor();
                       Tensor gwts = wantWeights ? Tensor::zeros(wts.shape(), g.dtype()) : Tensor();
                       Tensor gdep = wantDepth ? Tensor::empty(dep.shape(), g.dtype()) : Tensor();
                       Launch l("sweep", "sweep_meanvar_backward", g.dtype(), options);
                       addCommon(l, d)
                           .arg(cams)
                           .real(d.rfx)
                           .real(d.rfy)
                           .real(d.rcx)
                           .real(d.rcy)
                           .arg(dep)
                           .arg(src)
                           .arg(hasWeights ? 1 : 0)
                           .arg(hasWeights ? wts : src)
                           .arg(g)
                           .arg(wantSrc ? 1 : 0)
                           .arg(wantSrc ? gsrc : g) // unused placeholders when not wanted
                           .arg(wantWeights ? 1 : 0)
                           .arg(wantWeights ? gwts : g)
                           .arg(wantDepth ? 1 : 0)
                           .arg(wantDepth ? gdep : g)
                           .run3(d.w, d.h, d.S);
                       return std::vector<Tensor>{gsrc, gwts, gdep};
                     });
}

} // namespace simpli::geometry

#include "simpli/ocl/ops_shape.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/buffer_pool.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_reduce.h"

#include <algorithm>
#include <memory>
#include <string>

namespace simpli::ocl {
namespace {

void checkDefined(const Tensor& x, const char* op) {
  if (!x.defined())
    fail(op, ": undefined tensor");
}

void checkNotEmpty(const Shape& out, const char* op, const std::string& what) {
  if (numelOf(out) == 0)
    fail(op, ": ", what, " gives the zero-size output ", toString(out));
}

/// dst[dstBase + view(dstStrides)] = src[srcBase + view(srcStrides)] over a view of `shape`.
/// Dimensions that are contiguous in both views are merged first, so that e.g. a concat along
/// channels becomes a copy of long contiguous runs; the kernel walks the last three dimensions
/// and this function loops over any leading ones (only genuinely 4-D+ permutes have them).
void stridedCopy(const Tensor& src, int64_t srcBase, const Shape& srcStrides, const Tensor& dst,
                 int64_t dstBase, const Shape& dstStrides, const Shape& shape, const char* op) {
  if (numelOf(shape) == 0)
    return;
  checkedInt(std::max(src.numel(), dst.numel()), op);
  Shape s, a, b;
  for (std::size_t d = 0; d < shape.size(); ++d) {
    if (shape[d] == 1)
      continue;
    if (!s.empty() && a.back() == srcStrides[d] * shape[d] &&
        b.back() == dstStrides[d] * shape[d]) {
      s.back() *= shape[d];
      a.back() = srcStrides[d];
      b.back() = dstStrides[d];
    } else {
      s.push_back(shape[d]);
      a.push_back(srcStrides[d]);
      b.push_back(dstStrides[d]);
    }
  }
  while (s.size() < 3) { // pad at the front to exactly three kernel dimensions
    s.insert(s.begin(), 1);
    a.insert(a.begin(), 0);
    b.insert(b.begin(), 0);
  }
  const std::size_t lead = s.size() - 3;
  const Shape leadShape(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(lead));
  const int64_t n0 = s[lead + 2], n1 = s[lead + 1], n2 = s[lead];
  // Fixed work-group shapes (PoCL compiles one kernel per local size): long rows, or many
  // short rows (e.g. a channel-last permute with few channels).
  const std::size_t l0 = n0 >= 64 ? 64 : 4, l1 = n0 >= 64 ? 1 : 16;
  for (int64_t r = 0; r < numelOf(leadShape); ++r) {
    int64_t srcOff = srcBase, dstOff = dstBase, rest = r;
    for (int d = static_cast<int>(lead) - 1; d >= 0; --d) {
      const int64_t c = rest % leadShape[d];
      rest /= leadShape[d];
      srcOff += c * a[d];
      dstOff += c * b[d];
    }
    Launch("shape", "strided_copy", src.dtype())
        .arg(static_cast<int>(n0))
        .arg(static_cast<int>(n1))
        .arg(static_cast<int>(n2))
        .arg(src)
        .arg(static_cast<int>(srcOff))
        .arg(static_cast<int>(a[lead + 2]))
        .arg(static_cast<int>(a[lead + 1]))
        .arg(static_cast<int>(a[lead]))
        .arg(dst)
        .arg(static_cast<int>(dstOff))
        .arg(static_cast<int>(b[lead + 2]))
        .arg(static_cast<int>(b[lead + 1]))
        .arg(static_cast<int>(b[lead]))
        .run3(n0, n1, n2, l0, l1, 1);
  }
}

/// Python's slice.indices for one axis: normalised start and the element count.
std::pair<int64_t, int64_t> sliceRange(int64_t n, int64_t start, int64_t end, int64_t step) {
  const int64_t lower = step > 0 ? 0 : -1, upper = step > 0 ? n : n - 1;
  auto norm = [&](int64_t v) {
    if (v < 0)
      v += n;
    return std::clamp(v, lower, upper);
  };
  start = norm(start);
  end = norm(end);
  int64_t count = 0;
  if (step > 0 && end > start)
    count = (end - start + step - 1) / step;
  else if (step < 0 && start > end)
    count = (start - end - step - 1) / -step;
  return {start, count};
}

} // namespace

Tensor slice(const Tensor& x, int axis, int64_t start, int64_t end, int64_t step) {
  checkDefined(x, "slice");
  const int a = normaliseAxis(axis, x.dim(), "slice", x.shape());
  if (step == 0)
    fail("slice: step 0 on axis ", axis, " of ", x.describe());
  const auto [first, count] = sliceRange(x.shape()[a], start, end, step);
  Shape outShape = x.shape();
  outShape[a] = count;
  checkNotEmpty(outShape, "slice",
                "range [" + std::to_string(start) + ":" + std::to_string(end) + ":" +
                    std::to_string(step) + "] on axis " + std::to_string(axis) + " of " +
                    x.describe());
  Shape viewStrides = stridesOf(x.shape());
  const int64_t base = first * viewStrides[a];
  viewStrides[a] *= step;
  Tensor out = Tensor::empty(outShape, x.dtype());
  stridedCopy(x, base, viewStrides, out, 0, stridesOf(outShape), outShape, "slice");
  return record("slice", out, {x}, [xs = x.shape(), base, viewStrides](const Tensor& g) {
    // Scatter the gradient back into the sliced positions of a zero tensor.
    Tensor gx = Tensor::zeros(xs, g.dtype());
    stridedCopy(g, 0, stridesOf(g.shape()), gx, base, viewStrides, g.shape(), "slice backward");
    return std::vector<Tensor>{gx};
  });
}

Tensor concat(const std::vector<Tensor>& xs, int axis) {
  if (xs.empty())
    fail("concat: no tensors to join");
  for (std::size_t k = 0; k < xs.size(); ++k)
    if (!xs[k].defined())
      fail("concat: tensor ", k, " is undefined");
  const Tensor& first = xs.front();
  const int a = normaliseAxis(axis, first.dim(), "concat", first.shape());
  Shape outShape = first.shape();
  outShape[a] = 0;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    const Tensor& x = xs[k];
    bool compatible = x.dtype() == first.dtype() && x.dim() == first.dim();
    for (int d = 0; compatible && d < x.dim(); ++d)
      compatible = d == a || x.shape()[d] == first.shape()[d];
    if (!compatible)
      fail("concat: tensor ", k, " ", x.describe(), " does not match tensor 0 ", first.describe(),
           " outside axis ", axis);
    outShape[a] += x.shape()[a];
  }
  checkNotEmpty(outShape, "concat", "joining " + std::to_string(xs.size()) + " tensors");
  Tensor out = Tensor::empty(outShape, first.dtype());
  const Shape outStrides = stridesOf(outShape);
  std::vector<int64_t> offsets;
  int64_t offset = 0;
  for (const Tensor& x : xs) {
    offsets.push_back(offset);
    stridedCopy(x, 0, stridesOf(x.shape()), out, offset * outStrides[a], outStrides, x.shape(),
                "concat");
    offset += x.shape()[a];
  }
  if (!needsGrad(xs))
    return out;
  std::vector<Shape> shapes;
  std::vector<bool> wanted;
  for (const Tensor& x : xs) {
    shapes.push_back(x.shape());
    wanted.push_back(x.requiresGrad());
  }
  return record("concat", out, xs, [a, shapes, wanted, offsets](const Tensor& g) {
    std::vector<Tensor> grads(shapes.size());
    const Shape gStrides = stridesOf(g.shape());
    for (std::size_t k = 0; k < shapes.size(); ++k) {
      if (!wanted[k])
        continue;
      grads[k] = Tensor::empty(shapes[k], g.dtype());
      stridedCopy(g, offsets[k] * gStrides[a], gStrides, grads[k], 0, stridesOf(shapes[k]),
                  shapes[k], "concat backward");
    }
    return grads;
  });
}

Tensor permute(const Tensor& x, const std::vector<int>& perm) {
  checkDefined(x, "permute");
  auto describePerm = [&perm] {
    std::string s = "(";
    for (std::size_t d = 0; d < perm.size(); ++d)
      s += (d ? ", " : "") + std::to_string(perm[d]);
    return s + ")";
  };
  if (static_cast<int>(perm.size()) != x.dim())
    fail("permute: permutation ", describePerm(), " has ", perm.size(), " entries for ",
         x.describe());
  std::vector<int> p(perm.size());
  std::vector<bool> seen(perm.size(), false);
  for (std::size_t d = 0; d < perm.size(); ++d) {
    const int r = static_cast<int>(perm.size());
    const int v = perm[d] < 0 ? perm[d] + r : perm[d];
    if (v < 0 || v >= r || seen[v])
      fail("permute: ", describePerm(), " is not a permutation of the axes of ", x.describe());
    seen[v] = true;
    p[d] = v;
  }
  const Shape inStrides = stridesOf(x.shape());
  Shape outShape(p.size()), viewStrides(p.size());
  for (std::size_t d = 0; d < p.size(); ++d) {
    outShape[d] = x.shape()[p[d]];
    viewStrides[d] = inStrides[p[d]];
  }
  Tensor out = Tensor::empty(outShape, x.dtype());
  stridedCopy(x, 0, viewStrides, out, 0, stridesOf(outShape), outShape, "permute");
  return record("permute", out, {x}, [p](const Tensor& g) {
    std::vector<int> inverse(p.size());
    for (std::size_t d = 0; d < p.size(); ++d)
      inverse[p[d]] = static_cast<int>(d);
    return std::vector<Tensor>{permute(g, inverse)};
  });
}

Tensor transpose(const Tensor& x, int axisA, int axisB) {
  checkDefined(x, "transpose");
  const int a = normaliseAxis(axisA, x.dim(), "transpose", x.shape());
  const int b = normaliseAxis(axisB, x.dim(), "transpose", x.shape());
  std::vector<int> perm(x.dim());
  for (int d = 0; d < x.dim(); ++d)
    perm[d] = d;
  std::swap(perm[a], perm[b]);
  return permute(x, perm);
}

Tensor pad(const Tensor& x, const std::vector<std::pair<int64_t, int64_t>>& padding, PadMode mode) {
  checkDefined(x, "pad");
  if (static_cast<int>(padding.size()) != x.dim())
    fail("pad: ", padding.size(), " (before, after) pairs for ", x.describe(),
         " (one per axis needed)");
  Shape outShape = x.shape(), before(x.dim());
  for (int d = 0; d < x.dim(); ++d) {
    const auto [lo, hi] = padding[d];
    if (lo < 0 || hi < 0)
      fail("pad: negative padding (", lo, ", ", hi, ") on axis ", d, " of ", x.describe());
    if (mode == PadMode::Replicate && x.shape()[d] == 0 && lo + hi > 0)
      fail("pad: replicate padding of the empty axis ", d, " of ", x.describe());
    outShape[d] += lo + hi;
    before[d] = lo;
  }
  checkNotEmpty(outShape, "pad", "padding " + x.describe());
  Tensor out;
  if (mode == PadMode::Zeros) {
    // Zeros, then the input copied into the interior (two fast passes; the gather kernel
    // below needs an integer division per element per axis).
    out = Tensor::zeros(outShape, x.dtype());
    const Shape outStrides = stridesOf(outShape);
    int64_t base = 0;
    for (int d = 0; d < x.dim(); ++d)
      base += before[d] * outStrides[d];
    stridedCopy(x, 0, stridesOf(x.shape()), out, base, outStrides, x.shape(), "pad");
  } else {
    out = Tensor::empty(outShape, x.dtype());
    const int n = checkedInt(out.numel(), "pad");
    Launch("shape", "pad_replicate_forward", x.dtype())
        .arg(n)
        .arg(x.dim())
        .arg(toInt8(outShape))
        .arg(toInt8(x.shape()))
        .arg(toInt8(before))
        .arg(x)
        .arg(out)
        .run(n);
  }
  return record("pad", out, {x}, [xs = x.shape(), before, mode](const Tensor& g) {
    Tensor gx = Tensor::empty(xs, g.dtype());
    const Shape gStrides = stridesOf(g.shape());
    if (mode == PadMode::Zeros) {
      // The gradient of zero padding is the interior of the output gradient.
      int64_t base = 0;
      for (std::size_t d = 0; d < xs.size(); ++d)
        base += before[d] * gStrides[d];
      stridedCopy(g, base, gStrides, gx, 0, stridesOf(xs), xs, "pad backward");
    } else {
      const int m = checkedInt(gx.numel(), "pad backward");
      Launch("shape", "pad_replicate_backward", g.dtype())
          .arg(m)
          .arg(static_cast<int>(xs.size()))
          .arg(toInt8(g.shape()))
          .arg(toInt8(xs))
          .arg(toInt8(before))
          .arg(g)
          .arg(gx)
          .run(m);
    }
    return std::vector<Tensor>{gx};
  });
}

Tensor indexSelect(const Tensor& x, int axis, const std::vector<int64_t>& indices) {
  checkDefined(x, "indexSelect");
  const int a = normaliseAxis(axis, x.dim(), "indexSelect", x.shape());
  const int64_t n = x.shape()[a];
  std::vector<cl_int> idx(indices.size());
  for (std::size_t j = 0; j < indices.size(); ++j) {
    const int64_t v = indices[j] < 0 ? indices[j] + n : indices[j];
    if (v < 0 || v >= n)
      fail("indexSelect: index ", indices[j], " (entry ", j, ") is out of range for axis ", axis,
           " of ", x.describe());
    idx[j] = static_cast<cl_int>(v);
  }
  Shape outShape = x.shape();
  outShape[a] = static_cast<int64_t>(indices.size());
  checkNotEmpty(outShape, "indexSelect",
                std::to_string(indices.size()) + " indices into " + x.describe());
  int64_t outer = 1, inner = 1;
  for (int d = 0; d < a; ++d)
    outer *= x.shape()[d];
  for (int d = a + 1; d < x.dim(); ++d)
    inner *= x.shape()[d];
  // The indices live in a small device buffer kept alive by the backward closure. The write
  // is blocking (the host vector dies here), which costs one queue synchronisation per call.
  std::shared_ptr<Buffer> table = Device::current().pool().acquire(idx.size() * sizeof(cl_int));
  checkCl(clEnqueueWriteBuffer(Device::current().queue(), table->mem(), CL_TRUE, 0,
                               idx.size() * sizeof(cl_int), idx.data(), 0, nullptr, nullptr),
          "indexSelect: index upload");
  const int o = checkedInt(outer, "indexSelect"), in = checkedInt(inner, "indexSelect");
  const int count = checkedInt(static_cast<int64_t>(idx.size()), "indexSelect");
  Tensor out = Tensor::empty(outShape, x.dtype());
  Launch("shape", "index_select_forward", x.dtype())
      .arg(o)
      .arg(static_cast<int>(n))
      .arg(in)
      .arg(count)
      .arg(table->mem())
      .arg(x)
      .arg(out)
      .run(out.numel());
  return record("indexSelect", out, {x}, [xs = x.shape(), table, o, n, in, count](const Tensor& g) {
    Tensor gx = Tensor::empty(xs, g.dtype());
    Launch("shape", "index_select_backward", g.dtype())
        .arg(o)
        .arg(static_cast<int>(n))
        .arg(in)
        .arg(count)
        .arg(table->mem())
        .arg(g)
        .arg(gx)
        .run(gx.numel());
    return std::vector<Tensor>{gx};
  });
}

} // namespace simpli::ocl

// Shape ops through the harness (slice, concat, permute/transpose, pad, indexSelect,
// squeeze/unsqueeze) on odd shapes with size-1 dimensions up to rank 6, and their bad use.
#include "op_harness.h"
#include "test_support.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/ops_elementwise.h"
#include "simpli/ocl/ops_reduce.h"
#include "simpli/ocl/ops_shape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>

using namespace simpli;
using namespace simpli::test;
using ocl::Dtype;

namespace {

using Coords = std::vector<int64_t>;

Coords coordsOf(int64_t i, const Shape& s) {
  Coords c(s.size());
  for (int d = static_cast<int>(s.size()) - 1; d >= 0; --d) {
    c[d] = i % s[d];
    i /= s[d];
  }
  return c;
}

int64_t flatOf(const Coords& c, const Shape& s) {
  int64_t i = 0;
  for (std::size_t d = 0; d < s.size(); ++d)
    i = i * s[d] + c[d];
  return i;
}

/// out[i] = source(coords of i) for every element of outShape; source returns the value.
std::vector<double> gatherRef(const Shape& outShape,
                              const std::function<double(const Coords&)>& source) {
  std::vector<double> out(static_cast<std::size_t>(ocl::numelOf(outShape)));
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = source(coordsOf(static_cast<int64_t>(i), outShape));
  return out;
}

} // namespace

TEST(Shape, SliceAgainstReference) {
  struct Case {
    Shape shape;
    int axis;
    int64_t start, end, step;
  };
  const Case cases[] = {
      {{5, 7}, 1, 1, 6, 2},       {{3, 1, 4}, -1, -3, 100, 1},      {{3, 5, 2}, 1, -1, -4, -1},
      {{4, 3}, 0, 100, -100, -2}, {{2, 1, 3, 1, 2, 3}, 2, 0, 3, 2}, {{7}, 0, -7, 7, 3},
      {{1, 1}, 0, 0, 1, 1},
  };
  for (const auto& k : cases) {
    // Expected indices along the axis, straight from Python's rules.
    const int a = k.axis < 0 ? k.axis + static_cast<int>(k.shape.size()) : k.axis;
    const int64_t n = k.shape[a];
    std::vector<int64_t> picked;
    {
      int64_t s = k.start < 0 ? k.start + n : k.start, e = k.end < 0 ? k.end + n : k.end;
      if (k.step > 0) {
        s = std::clamp<int64_t>(s, 0, n);
        e = std::clamp<int64_t>(e, 0, n);
        for (int64_t v = s; v < e; v += k.step)
          picked.push_back(v);
      } else {
        s = std::clamp<int64_t>(s, -1, n - 1);
        e = std::clamp<int64_t>(e, -1, n - 1);
        for (int64_t v = s; v > e; v += k.step)
          picked.push_back(v);
      }
    }
    Shape outShape = k.shape;
    outShape[a] = static_cast<int64_t>(picked.size());
    OpCase c;
    c.name = "slice " + ocl::toString(k.shape) + " axis " + std::to_string(k.axis);
    c.inputShapes = {k.shape};
    c.device = [k](const std::vector<ocl::Tensor>& in) {
      return ocl::slice(in[0], k.axis, k.start, k.end, k.step);
    };
    c.reference = [k, a, picked, outShape](const HostInputs& in) {
      return gatherRef(outShape, [&](Coords co) {
        co[a] = picked[co[a]];
        return in[0][flatOf(co, k.shape)];
      });
    };
    checkOp(c);
  }
}

TEST(Shape, ConcatAgainstReference) {
  struct Case {
    std::vector<Shape> shapes;
    int axis;
  };
  const Case cases[] = {
      {{{2, 3, 4}, {2, 1, 4}, {2, 5, 4}}, 1},
      {{{1, 3}, {4, 3}}, 0},
      {{{3, 2}, {3, 5}, {3, 1}}, -1},
      {{{7}}, 0},
      {{{2, 1, 3, 1, 2, 1}, {2, 1, 3, 1, 2, 3}}, 5},
      {{{1, 2, 1, 3, 1, 1}, {1, 2, 2, 3, 1, 1}}, 2},
  };
  for (const auto& k : cases) {
    const int rank = static_cast<int>(k.shapes[0].size());
    const int a = k.axis < 0 ? k.axis + rank : k.axis;
    Shape outShape = k.shapes[0];
    outShape[a] = 0;
    for (const auto& s : k.shapes)
      outShape[a] += s[a];
    OpCase c;
    c.name = "concat axis " + std::to_string(k.axis) + " of " + ocl::toString(k.shapes[0]);
    c.inputShapes = k.shapes;
    c.device = [k](const std::vector<ocl::Tensor>& in) { return ocl::concat(in, k.axis); };
    c.reference = [k, a, outShape](const HostInputs& in) {
      return gatherRef(outShape, [&](Coords co) {
        std::size_t t = 0;
        while (co[a] >= k.shapes[t][a]) {
          co[a] -= k.shapes[t][a];
          ++t;
        }
        return in[t][flatOf(co, k.shapes[t])];
      });
    };
    checkOp(c);
  }
}

TEST(Shape, PermuteAndTransposeAgainstReference) {
  struct Case {
    Shape shape;
    std::vector<int> perm;
  };
  const Case cases[] = {
      {{2, 3, 5}, {2, 0, 1}},
      {{1, 4, 1, 3}, {3, 1, 0, 2}},
      {{2, 1, 3, 2, 1, 3}, {5, 4, 3, 2, 1, 0}},
      {{2, 3, 2, 3, 2, 3}, {5, 3, 1, 4, 2, 0}}, // nothing merges: host loop over leading dims
      {{3, 5, 2}, {0, 2, 1}},                   // channel-last style: short innermost runs
      {{6}, {0}},
      {{2, 3, 4}, {-1, 0, 1}},
  };
  for (const auto& k : cases) {
    const int rank = static_cast<int>(k.shape.size());
    std::vector<int> p = k.perm;
    for (auto& v : p)
      v = v < 0 ? v + rank : v;
    Shape outShape(rank);
    for (int d = 0; d < rank; ++d)
      outShape[d] = k.shape[p[d]];
    OpCase c;
    c.name = "permute " + ocl::toString(k.shape);
    c.inputShapes = {k.shape};
    c.device = [k](const std::vector<ocl::Tensor>& in) { return ocl::permute(in[0], k.perm); };
    c.reference = [k, p, outShape](const HostInputs& in) {
      return gatherRef(outShape, [&](const Coords& co) {
        Coords src(co.size());
        for (std::size_t d = 0; d < co.size(); ++d)
          src[p[d]] = co[d];
        return in[0][flatOf(src, k.shape)];
      });
    };
    checkOp(c);
  }
  OpCase t;
  t.name = "transpose [3, 1, 4, 2] axes 0, -1";
  t.inputShapes = {{3, 1, 4, 2}};
  t.device = [](const std::vector<ocl::Tensor>& in) { return ocl::transpose(in[0], 0, -1); };
  t.reference = [](const HostInputs& in) {
    return gatherRef({2, 1, 4, 3}, [&](const Coords& co) {
      return in[0][flatOf({co[3], co[1], co[2], co[0]}, {3, 1, 4, 2})];
    });
  };
  checkOp(t);
}

TEST(Shape, PadAgainstReference) {
  using Padding = std::vector<std::pair<int64_t, int64_t>>;
  struct Case {
    Shape shape;
    Padding padding;
  };
  const Case cases[] = {
      {{3, 4}, {{1, 2}, {0, 3}}},
      {{2, 1, 3, 5}, {{0, 0}, {1, 1}, {2, 0}, {1, 1}}},
      {{1, 1}, {{2, 1}, {1, 2}}},
      {{5}, {{0, 0}}},
      {{2, 1, 2, 1, 3, 2}, {{0, 1}, {0, 0}, {1, 0}, {2, 2}, {0, 0}, {1, 1}}},
  };
  for (ocl::PadMode mode : {ocl::PadMode::Zeros, ocl::PadMode::Replicate}) {
    const bool replicate = mode == ocl::PadMode::Replicate;
    for (const auto& k : cases) {
      Shape outShape = k.shape;
      for (std::size_t d = 0; d < outShape.size(); ++d)
        outShape[d] += k.padding[d].first + k.padding[d].second;
      OpCase c;
      c.name = std::string(replicate ? "pad replicate " : "pad zeros ") + ocl::toString(k.shape);
      c.inputShapes = {k.shape};
      c.device = [k, mode](const std::vector<ocl::Tensor>& in) {
        return ocl::pad(in[0], k.padding, mode);
      };
      c.reference = [k, replicate, outShape](const HostInputs& in) {
        return gatherRef(outShape, [&](Coords co) {
          for (std::size_t d = 0; d < co.size(); ++d) {
            co[d] -= k.padding[d].first;
            if (co[d] < 0 || co[d] >= k.shape[d]) {
              if (!replicate)
                return 0.0;
              co[d] = std::clamp<int64_t>(co[d], 0, k.shape[d] - 1);
            }
          }
          return in[0][flatOf(co, k.shape)];
        });
      };
      checkOp(c);
    }
  }
}

TEST(Shape, IndexSelectAgainstReference) {
  const std::vector<int64_t> indices = {4, 0, 0, -1, 2};
  OpCase c;
  c.name = "indexSelect [3, 5, 2] axis 1";
  c.inputShapes = {{3, 5, 2}};
  c.device = [&](const std::vector<ocl::Tensor>& in) {
    return ocl::indexSelect(in[0], 1, indices);
  };
  c.reference = [&](const HostInputs& in) {
    return gatherRef({3, 5, 2}, [&](Coords co) {
      co[1] = (indices[co[1]] + 5) % 5;
      return in[0][flatOf(co, {3, 5, 2})];
    });
  };
  checkOp(c);
  OpCase d;
  d.name = "indexSelect [4, 1] axis 0";
  d.inputShapes = {{4, 1}};
  d.device = [](const std::vector<ocl::Tensor>& in) { return ocl::indexSelect(in[0], -2, {3}); };
  d.reference = [](const HostInputs& in) { return std::vector<double>{in[0][3]}; };
  checkOp(d);
}

TEST(Shape, SqueezeUnsqueezeAreViewsOnTheTape) {
  ocl::Tensor x = ocl::Tensor::fromHost(std::vector<double>{1, 2, 3}, {3, 1}, Dtype::F64);
  x.setRequiresGrad(true);
  ocl::Tensor s = ocl::squeeze(x, -1);
  EXPECT_EQ(s.shape(), (Shape{3}));
  ocl::Tensor u = ocl::unsqueeze(s, 0);
  EXPECT_EQ(u.shape(), (Shape{1, 3}));
  EXPECT_EQ(ocl::unsqueeze(s, -1).shape(), (Shape{3, 1}));
  EXPECT_EQ(ocl::unsqueeze(s, 1).shape(), (Shape{3, 1}));
  ocl::Tensor w = ocl::Tensor::fromHost(std::vector<double>{1, 10, 100}, {1, 3}, Dtype::F64);
  ocl::sumAll(ocl::mul(u, w)).backward();
  EXPECT_EQ(x.grad().toVector(), (std::vector<double>{1, 10, 100}));
}

TEST(Shape, ConcatGradientSkipsInputsWithoutGrad) {
  ocl::Tensor a = ocl::Tensor::fromHost(std::vector<double>{1, 2}, {2}, Dtype::F64);
  ocl::Tensor b = ocl::Tensor::fromHost(std::vector<double>{3, 4, 5}, {3}, Dtype::F64);
  b.setRequiresGrad(true);
  ocl::Tensor w = ocl::Tensor::fromHost(std::vector<double>{1, 2, 3, 4, 5}, {5}, Dtype::F64);
  ocl::sumAll(ocl::mul(ocl::concat({a, b}, 0), w)).backward();
  EXPECT_FALSE(a.grad().defined());
  EXPECT_EQ(b.grad().toVector(), (std::vector<double>{3, 4, 5}));
}

TEST(Shape, LargeCopiesMatchAcrossKernelShapes) {
  // Long contiguous runs, medium runs and single-element runs take different work-group
  // shapes; all must agree with the host.
  ocl::Tensor x = ocl::Tensor::arange(3 * 70 * 9, 0.0, 1.0, Dtype::F64).viewAs({3, 70, 9});
  const auto v = x.toVector();
  const auto a = ocl::slice(x, 1, 3, 70, 1).toVector(); // runs of 67 * 9
  const auto b = ocl::slice(x, 2, 1, 9, 1).toVector();  // runs of 8
  const auto p = ocl::permute(x, {2, 1, 0}).toVector(); // runs of 1
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 70; ++j)
      for (int k = 0; k < 9; ++k) {
        const double e = v[(i * 70 + j) * 9 + k];
        if (j >= 3) {
          ASSERT_EQ(a[(i * 67 + j - 3) * 9 + k], e);
        }
        if (k >= 1) {
          ASSERT_EQ(b[(i * 70 + j) * 8 + k - 1], e);
        }
        ASSERT_EQ(p[(k * 70 + j) * 3 + i], e);
      }
}

TEST(Shape, BadUseThrowsNamingOpAndShapes) {
  auto x = ocl::Tensor::zeros({2, 3});
  expectError([&] { ocl::slice(x, 2, 0, 1); }, {"slice", "[2, 3]"});
  expectError([&] { ocl::slice(x, -3, 0, 1); }, {"slice", "[2, 3]"});
  expectError([&] { ocl::slice(x, 1, 2, 1); }, {"slice", "zero-size", "[2, 3]"});
  expectError([&] { ocl::slice(x, 1, 0, 3, 0); }, {"slice", "step 0", "[2, 3]"});
  expectError(
      [&] {
        ocl::concat({x, ocl::Tensor::zeros({3, 3})}, 1);
      },
      {"concat", "[3, 3]", "[2, 3]"});
  expectError([&] { ocl::concat({x, ocl::Tensor::zeros({2, 3, 1})}, 0); }, {"concat", "[2, 3, 1]"});
  expectError(
      [&] {
        ocl::concat({x, ocl::Tensor::zeros({2, 3}, Dtype::F64)}, 0);
      },
      {"concat", "f64[2, 3]"});
  expectError([&] { ocl::concat({x}, 2); }, {"concat", "[2, 3]"});
  expectError([] { ocl::concat({}, 0); }, {"concat"});
  expectError([] { ocl::concat({ocl::Tensor::zeros({0, 3})}, 0); }, {"concat", "zero-size"});
  expectError([&] { ocl::permute(x, {0, 0}); }, {"permute", "(0, 0)", "[2, 3]"});
  expectError([&] { ocl::permute(x, {0}); }, {"permute", "[2, 3]"});
  expectError([&] { ocl::permute(x, {0, 2}); }, {"permute", "[2, 3]"});
  expectError([&] { ocl::transpose(x, 0, 2); }, {"transpose", "[2, 3]"});
  expectError([&] { ocl::pad(x, {{0, 1}}); }, {"pad", "[2, 3]"});
  expectError([&] { ocl::pad(x, {{0, 1}, {-1, 0}}); }, {"pad", "negative", "[2, 3]"});
  expectError(
      [] {
        ocl::pad(ocl::Tensor::zeros({0, 2}), {{1, 0}, {0, 0}}, ocl::PadMode::Replicate);
      },
      {"pad", "[0, 2]"});
  expectError([&] { ocl::indexSelect(x, 1, {3}); }, {"indexSelect", "3", "[2, 3]"});
  expectError([&] { ocl::indexSelect(x, 0, {}); }, {"indexSelect", "zero-size"});
  expectError([&] { ocl::indexSelect(x, 5, {0}); }, {"indexSelect", "[2, 3]"});
  expectError([&] { ocl::squeeze(x, 0); }, {"squeeze", "[2, 3]"});
  expectError([&] { ocl::unsqueeze(x, 3); }, {"unsqueeze", "[2, 3]"});
  expectError([] { ocl::unsqueeze(ocl::Tensor::zeros({1, 1, 1, 1, 1, 1}), 0); }, {"unsqueeze"});
  expectError([] { ocl::slice(ocl::Tensor(), 0, 0, 1); }, {"slice", "undefined"});
}

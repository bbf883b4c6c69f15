#include "simpli/ocl/ops_elementwise.h"

#include "elementwise_op_codes.h" // kernels/, shared with elementwise.cl
#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"

#include <algorithm>

namespace simpli::ocl {
namespace {

enum BinaryOp {
  kAdd = OP_ADD,
  kSub = OP_SUB,
  kMul = OP_MUL,
  kDiv = OP_DIV,
  kMax = OP_MAX,
  kMin = OP_MIN,
  kGe = OP_GE,
  kLe = OP_LE
};
enum UnaryOp {
  kNeg = U_NEG,
  kExp = U_EXP,
  kLog = U_LOG,
  kSqrt = U_SQRT,
  kSquare = U_SQUARE,
  kAbs = U_ABS,
  kRelu = U_RELU,
  kElu = U_ELU,
  kSigmoid = U_SIGMOID,
  kTanh = U_TANH,
  kSoftplus = U_SOFTPLUS,
  kAddScalar = U_ADD_SCALAR,
  kMulScalar = U_MUL_SCALAR,
  kClamp = U_CLAMP,
  kPowScalar = U_POW_SCALAR
};

const char* binaryName(int op) {
  static const char* names[] = {"add", "sub", "mul", "div", "maximum", "minimum", "ge", "le"};
  return names[op];
}

void checkOperands(const Tensor& a, const Tensor& b, const char* op) {
  if (!a.defined() || !b.defined())
    fail(op, ": undefined operand");
  if (a.dtype() != b.dtype())
    fail(op, ": dtype mismatch ", a.describe(), " vs ", b.describe());
}

// Strides of `shape` as seen from an output of rank `rank`: left-padded with size-1 dims,
// stride 0 on broadcast dimensions.
Shape broadcastStrides(const Shape& shape, const Shape& outShape) {
  const std::size_t rank = outShape.size();
  Shape padded(rank - shape.size(), 1);
  padded.insert(padded.end(), shape.begin(), shape.end());
  Shape strides = stridesOf(padded);
  for (std::size_t d = 0; d < rank; ++d)
    if (padded[d] == 1 && outShape[d] != 1)
      strides[d] = 0;
  return strides;
}

std::string binaryOptions(int op) {
  return "-DBINARY_OP=" + std::to_string(op);
}

std::string unaryOptions(int op) {
  return "-DUNARY_OP=" + std::to_string(op);
}

// The output's dimensions with both operands' strides, size-1 dimensions dropped and
// neighbours merged where both operands are contiguous across them (so [N, C, H, W] + [C, 1, 1]
// becomes [N, C, H*W] with b strides [0, 1, 0]). Innermost last.
struct Collapsed {
  std::vector<int64_t> size, sa, sb;
};

Collapsed collapseBroadcast(const Shape& out, const Shape& sa, const Shape& sb) {
  Collapsed c;
  for (std::size_t d = 0; d < out.size(); ++d) {
    if (out[d] == 1)
      continue;
    if (!c.size.empty() && c.sa.back() == sa[d] * out[d] && c.sb.back() == sb[d] * out[d]) {
      c.size.back() *= out[d];
      c.sa.back() = sa[d];
      c.sb.back() = sb[d];
      continue;
    }
    c.size.push_back(out[d]);
    c.sa.push_back(sa[d]);
    c.sb.push_back(sb[d]);
  }
  return c;
}

Tensor binaryRaw(int op, const Tensor& a, const Tensor& b) {
  const char* name = binaryName(op);
  checkOperands(a, b, name);
  const Shape outShape = broadcastShapes(a.shape(), b.shape(), name);
  Tensor out = Tensor::empty(outShape, a.dtype());
  const int n = checkedInt(out.numel(), name);
  if (a.shape() == b.shape()) {
    Launch("elementwise", "binary_same", a.dtype(), binaryOptions(op))
        .arg(n)
        .arg(op)
        .arg(a)
        .arg(b)
        .arg(out)
        .run(n);
    return out;
  }
  Collapsed c = collapseBroadcast(outShape, broadcastStrides(a.shape(), outShape),
                                  broadcastStrides(b.shape(), outShape));
  if (c.size.size() <= 3) {
    while (c.size.size() < 3) { // pad on the outside
      c.size.insert(c.size.begin(), 1);
      c.sa.insert(c.sa.begin(), 0);
      c.sb.insert(c.sb.begin(), 0);
    }
    // Inner runs of >= 16: a 3-D range without index divisions (measured on PoCL: see
    // docs/benchmarks.md, issue 13), work groups of 64 or 16 along the run.
    if (c.size[2] >= 16) {
      Launch grid("elementwise", "binary_broadcast3_grid", a.dtype(), binaryOptions(op));
      grid.arg(op).arg(static_cast<int>(c.size[1])).arg(static_cast<int>(c.size[2])).arg(a);
      for (int64_t v : c.sa)
        grid.arg(static_cast<int>(v));
      grid.arg(b);
      for (int64_t v : c.sb)
        grid.arg(static_cast<int>(v));
      grid.arg(out).run3(c.size[2], c.size[1], c.size[0], c.size[2] >= 64 ? 64 : 16, 1, 1);
      return out;
    }
    Launch launch("elementwise", "binary_broadcast3", a.dtype(), binaryOptions(op));
    launch.arg(n).arg(op).arg(static_cast<int>(c.size[1])).arg(static_cast<int>(c.size[2]));
    launch.arg(a);
    for (int64_t v : c.sa)
      launch.arg(static_cast<int>(v));
    launch.arg(b);
    for (int64_t v : c.sb)
      launch.arg(static_cast<int>(v));
    launch.arg(out).run(n);
  } else {
    Launch("elementwise", "binary_broadcast", a.dtype(), binaryOptions(op))
        .arg(n)
        .arg(op)
        .arg(static_cast<int>(outShape.size()))
        .arg(toInt8(outShape))
        .arg(a)
        .arg(toInt8(broadcastStrides(a.shape(), outShape)))
        .arg(b)
        .arg(toInt8(broadcastStrides(b.shape(), outShape)))
        .arg(out)
        .run(n);
  }
  return out;
}

Tensor unaryRaw(int op, const Tensor& x, double p0, double p1) {
  if (!x.defined())
    fail("unary op: undefined operand");
  Tensor y = Tensor::empty(x.shape(), x.dtype());
  const int n = checkedInt(x.numel(), "unary op");
  Launch("elementwise", "unary_forward", x.dtype(), unaryOptions(op))
      .arg(n)
      .arg(op)
      .real(p0)
      .real(p1)
      .arg(x)
      .arg(y)
      .run(n);
  return y;
}

Tensor unary(const char* name, int op, const Tensor& x, double p0 = 0.0, double p1 = 0.0) {
  Tensor y = unaryRaw(op, x, p0, p1);
  if (!needsGrad({x}))
    return y;
  Tensor xs = x.detach(), ys = y.detach();
  return record(name, y, {x}, [op, p0, p1, xs, ys](const Tensor& gy) {
    Tensor gx = Tensor::empty(xs.shape(), xs.dtype());
    const int n = static_cast<int>(xs.numel());
    Launch("elementwise", "unary_backward", xs.dtype(), unaryOptions(op))
        .arg(n)
        .arg(op)
        .real(p0)
        .real(p1)
        .arg(xs)
        .arg(ys)
        .arg(gy)
        .arg(gx)
        .run(n);
    return std::vector<Tensor>{gx};
  });
}

} // namespace

Shape broadcastShapes(const Shape& a, const Shape& b, const char* op) {
  const std::size_t rank = std::max(a.size(), b.size());
  Shape out(rank);
  for (std::size_t i = 0; i < rank; ++i) {
    const int64_t da = i < rank - a.size() ? 1 : a[i - (rank - a.size())];
    const int64_t db = i < rank - b.size() ? 1 : b[i - (rank - b.size())];
    if (da != db && da != 1 && db != 1)
      fail(op, ": shapes ", toString(a), " and ", toString(b), " cannot be broadcast");
    out[i] = da == 1 ? db : da;
  }
  return out;
}

Tensor sumToShape(const Tensor& x, const Shape& shape) {
  if (x.shape() == shape)
    return x;
  const Shape& src = x.shape();
  if (shape.size() > src.size())
    fail("sumToShape: cannot reduce ", x.describe(), " to ", toString(shape));
  Shape target(src.size() - shape.size(), 1);
  target.insert(target.end(), shape.begin(), shape.end());
  Shape reduced(src.size(), 1);
  for (std::size_t d = 0; d < src.size(); ++d) {
    if (target[d] == src[d])
      continue;
    if (target[d] != 1)
      fail("sumToShape: cannot reduce ", x.describe(), " to ", toString(shape));
    reduced[d] = src[d];
  }
  Tensor out = Tensor::empty(shape, x.dtype());
  Launch("elementwise", "sum_to_shape", x.dtype())
      .arg(checkedInt(out.numel(), "sumToShape"))
      .arg(static_cast<int>(src.size()))
      .arg(toInt8(target))
      .arg(toInt8(stridesOf(src)))
      .arg(toInt8(reduced))
      .arg(checkedInt(numelOf(reduced), "sumToShape"))
      .arg(x)
      .arg(out)
      .run(out.numel());
  const Shape srcShape = src;
  return record("sumToShape", out, {x}, [srcShape](const Tensor& g) {
    // Broadcasting back up: g + zeros of the source shape.
    return std::vector<Tensor>{add(g, Tensor::zeros(srcShape, g.dtype()))};
  });
}

Tensor add(const Tensor& a, const Tensor& b) {
  Tensor out = binaryRaw(kAdd, a, b);
  const Shape sa = a.shape(), sb = b.shape();
  return record("add", out, {a, b}, [sa, sb](const Tensor& g) {
    return std::vector<Tensor>{sumToShape(g, sa), sumToShape(g, sb)};
  });
}

Tensor sub(const Tensor& a, const Tensor& b) {
  Tensor out = binaryRaw(kSub, a, b);
  const Shape sa = a.shape(), sb = b.shape();
  return record("sub", out, {a, b}, [sa, sb](const Tensor& g) {
    return std::vector<Tensor>{sumToShape(g, sa), sumToShape(neg(g), sb)};
  });
}

Tensor mul(const Tensor& a, const Tensor& b) {
  Tensor out = binaryRaw(kMul, a, b);
  if (!needsGrad({a, b}))
    return out;
  Tensor ad = a.detach(), bd = b.detach();
  const bool ga = a.requiresGrad(), gb = b.requiresGrad();
  return record("mul", out, {a, b}, [ad, bd, ga, gb](const Tensor& g) {
    return std::vector<Tensor>{ga ? sumToShape(binaryRaw(kMul, g, bd), ad.shape()) : Tensor(),
                               gb ? sumToShape(binaryRaw(kMul, g, ad), bd.shape()) : Tensor()};
  });
}

Tensor div(const Tensor& a, const Tensor& b) {
  Tensor out = binaryRaw(kDiv, a, b);
  if (!needsGrad({a, b}))
    return out;
  Tensor ad = a.detach(), bd = b.detach(), od = out.detach();
  const bool ga = a.requiresGrad(), gb = b.requiresGrad();
  return record("div", out, {a, b}, [ad, bd, od, ga, gb](const Tensor& g) {
    Tensor gOverB = binaryRaw(kDiv, g, bd);
    Tensor gradA = ga ? sumToShape(gOverB, ad.shape()) : Tensor();
    // d(a/b)/db = -(a/b)/b
    Tensor gradB = gb ? sumToShape(neg(binaryRaw(kMul, gOverB, od)), bd.shape()) : Tensor();
    return std::vector<Tensor>{gradA, gradB};
  });
}

namespace {
Tensor extremum(int op, const Tensor& a, const Tensor& b) {
  Tensor out = binaryRaw(op, a, b);
  if (!needsGrad({a, b}))
    return out;
  Tensor ad = a.detach(), bd = b.detach();
  return record(binaryName(op), out, {a, b}, [op, ad, bd](const Tensor& g) {
    // `a` receives the gradient where it was chosen (ties go to a).
    Tensor maskA = binaryRaw(op == kMax ? kGe : kLe, ad, bd);
    Tensor maskB = unaryRaw(kAddScalar, unaryRaw(kNeg, maskA, 0, 0), 1.0, 0);
    return std::vector<Tensor>{sumToShape(binaryRaw(kMul, g, maskA), ad.shape()),
                               sumToShape(binaryRaw(kMul, g, maskB), bd.shape())};
  });
}
} // namespace

Tensor maximum(const Tensor& a, const Tensor& b) {
  return extremum(kMax, a, b);
}
Tensor minimum(const Tensor& a, const Tensor& b) {
  return extremum(kMin, a, b);
}

Tensor neg(const Tensor& x) {
  return unary("neg", kNeg, x);
}
Tensor exp(const Tensor& x) {
  return unary("exp", kExp, x);
}
Tensor log(const Tensor& x) {
  return unary("log", kLog, x);
}
Tensor sqrt(const Tensor& x) {
  return unary("sqrt", kSqrt, x);
}
Tensor square(const Tensor& x) {
  return unary("square", kSquare, x);
}
Tensor abs(const Tensor& x) {
  return unary("abs", kAbs, x);
}
Tensor relu(const Tensor& x) {
  return unary("relu", kRelu, x);
}
Tensor elu(const Tensor& x, double alpha) {
  return unary("elu", kElu, x, alpha);
}
Tensor sigmoid(const Tensor& x) {
  return unary("sigmoid", kSigmoid, x);
}
Tensor tanh(const Tensor& x) {
  return unary("tanh", kTanh, x);
}
Tensor softplus(const Tensor& x) {
  return unary("softplus", kSoftplus, x);
}
Tensor addScalar(const Tensor& x, double value) {
  return unary("addScalar", kAddScalar, x, value);
}
Tensor mulScalar(const Tensor& x, double value) {
  return unary("mulScalar", kMulScalar, x, value);
}
Tensor powScalar(const Tensor& x, double e) {
  return unary("powScalar", kPowScalar, x, e);
}
Tensor clamp(const Tensor& x, double low, double high) {
  if (!(low <= high))
    fail("clamp: low ", low, " > high ", high);
  return unary("clamp", kClamp, x, low, high);
}

void Tensor::addInPlace(const Tensor& other) {
  checkOperands(*this, other, "addInPlace");
  if (other.shape() != shape())
    fail("addInPlace: shape ", other.describe(), " does not match ", describe());
  const int n = checkedInt(numel(), "addInPlace");
  Launch("elementwise", "binary_same", dtype(), binaryOptions(kAdd))
      .arg(n)
      .arg(static_cast<int>(kAdd))
      .arg(*this)
      .arg(other)
      .arg(*this)
      .run(n);
}

void Tensor::mulInPlace(double factor) {
  const int n = checkedInt(numel(), "mulInPlace");
  Launch("elementwise", "unary_forward", dtype(), unaryOptions(kMulScalar))
      .arg(n)
      .arg(static_cast<int>(kMulScalar))
      .real(factor)
      .real(0.0)
      .arg(*this)
      .arg(*this)
      .run(n);
}

} // namespace simpli::ocl

#include "simpli/ocl/ops_attention.h"

#include "simpli/error.h"
#include "simpli/ocl/autograd.h"
#include "simpli/ocl/launch.h"
#include "simpli/ocl/ops_reduce.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace simpli::ocl {
namespace {

struct Dims {
  int N = 0, nq = 0, nk = 0, d = 0, dv = 0;
  bool sharedQ = false;
};

Dims checkShapes(const Tensor& q, const Tensor& k, const Tensor& v, double scale) {
  const char* op = "attention";
  for (const Tensor* t : {&q, &k, &v})
    if (!t->defined())
      fail(op, ": undefined input");
  if (k.dim() != 3 || v.dim() != 3 || (q.dim() != 3 && q.dim() != 2))
    fail(op, ": q ", q.describe(), ", k ", k.describe(), ", v ", v.describe(),
         " must be [N, nq, d] or [nq, d], [N, nk, d], [N, nk, dv]");
  Dims s;
  s.sharedQ = q.dim() == 2;
  s.N = checkedInt(k.size(0), op);
  s.nk = checkedInt(k.size(1), op);
  s.d = checkedInt(k.size(2), op);
  s.nq = checkedInt(q.size(-2), op);
  s.dv = checkedInt(v.size(2), op);
  if (q.size(-1) != s.d || v.size(0) != s.N || v.size(1) != s.nk ||
      (!s.sharedQ && q.size(0) != s.N))
    fail(op, ": q ", q.describe(), ", k ", k.describe(), ", v ", v.describe(),
         " do not match (q [N, nq, d] or [nq, d], k [N, nk, d], v [N, nk, dv])");
  if (q.dtype() != k.dtype() || q.dtype() != v.dtype())
    fail(op, ": dtypes differ: q ", q.describe(), ", k ", k.describe(), ", v ", v.describe());
  if (s.N == 0 || s.nq == 0 || s.nk == 0 || s.d == 0 || s.dv == 0)
    fail(op, ": empty input: q ", q.describe(), ", k ", k.describe(), ", v ", v.describe());
  if (!std::isfinite(scale))
    fail(op, ": scale ", scale, " is not finite");
  checkedInt(int64_t(s.N) * std::max({s.nq, s.nk}) * std::max(s.d, s.dv), op);
  return s;
}

Launch& dims(Launch& l, const Dims& s, double scale) {
  return l.arg(s.N).arg(s.nq).arg(s.nk).arg(s.d).arg(s.dv).arg(s.sharedQ ? 1 : 0).real(scale);
}

} // namespace

Tensor attention(const Tensor& q, const Tensor& k, const Tensor& v, double scale) {
  const Dims s = checkShapes(q, k, v, scale);
  const Dtype dt = k.dtype();
  Tensor out = Tensor::empty({s.N, s.nq, s.dv}, dt);
  Tensor stats = Tensor::empty({s.N, s.nq, 2}, dt);
  Launch forward("attention", "attention_forward", dt);
  dims(forward, s, scale).arg(q).arg(k).arg(v).arg(out).arg(stats);
  forward.run(int64_t(s.N) * s.nq);
  if (!needsGrad({q, k, v}))
    return out;
  return record("attention", out, {q, k, v},
                [qd = q.detach(), kd = k.detach(), vd = v.detach(), stats, s, scale,
                 want = std::array<bool, 3>{q.requiresGrad(), k.requiresGrad(), v.requiresGrad()}](
                    const Tensor& g) {
                  const Dtype dt = kd.dtype();
                  Tensor delta = Tensor::empty({s.N, s.nq}, dt);
                  Tensor gq = want[0] ? Tensor::empty({s.N, s.nq, s.d}, dt) : Tensor();
                  Launch query("attention", "attention_backward_query", dt);
                  dims(query, s, scale).arg(qd).arg(kd).arg(vd).arg(stats).arg(g).arg(delta);
                  query.arg(want[0] ? 1 : 0).arg(want[0] ? gq.buffer() : delta.buffer());
                  query.run(int64_t(s.N) * s.nq);
                  Tensor gk = want[1] ? Tensor::empty(kd.shape(), dt) : Tensor();
                  Tensor gv = want[2] ? Tensor::empty(vd.shape(), dt) : Tensor();
                  if (want[1] || want[2]) {
                    Launch key("attention", "attention_backward_key", dt);
                    dims(key, s, scale).arg(qd).arg(kd).arg(vd).arg(stats).arg(g).arg(delta);
                    key.arg(want[1] ? 1 : 0).arg(want[1] ? gk.buffer() : delta.buffer());
                    key.arg(want[2] ? 1 : 0).arg(want[2] ? gv.buffer() : delta.buffer());
                    key.run(int64_t(s.N) * s.nk);
                  }
                  if (want[0] && s.sharedQ)
                    gq = sum(gq, 0);
                  return std::vector<Tensor>{gq, gk, gv};
                });
}

} // namespace simpli::ocl

// Optimiser updates, one fused kernel per parameter tensor.

// PyTorch's Adam / AdamW step (torch.optim._single_tensor_adam, amsgrad off), elementwise:
//   AdamW: p *= decay (= 1 - lr wd);  Adam: grad += wd p  (the caller passes the unused one as
//   decay = 1 / wd = 0);
//   m = lerp(m, grad, 1 - beta1)  (torch.lerp's two-branch formula);
//   v = v beta2 + (1 - beta2) grad^2;
//   p -= step_size m / (sqrt(v) / bc2_sqrt + eps), step_size = lr / (1 - beta1^t),
//   bc2_sqrt = sqrt(1 - beta2^t). Scalars are computed on the host in double, like PyTorch.
__kernel void adam_step(const int n, const REAL decay, const REAL wd, const REAL one_minus_beta1,
                        const REAL beta2, const REAL one_minus_beta2, const REAL step_size,
                        const REAL bc2_sqrt, const REAL eps, __global REAL* p,
                        __global const REAL* g, __global REAL* m, __global REAL* v) {
  const int i = get_global_id(0);
  if (i >= n) return;
  REAL param = p[i] * decay;
  const REAL grad = g[i] + wd * param;
  const REAL w = one_minus_beta1;
  const REAL mi = m[i];
  const REAL mn = w < (REAL)0.5 ? mi + w * (grad - mi) : grad - (grad - mi) * (1 - w);
  const REAL vn = v[i] * beta2 + one_minus_beta2 * grad * grad;
  m[i] = mn;
  v[i] = vn;
  p[i] = param - step_size * (mn / (sqrt(vn) / bc2_sqrt + eps));
}

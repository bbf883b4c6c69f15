// MPI rendering into target cameras (spec §6.4): for every target pixel the unit
// ray from the target centre meets each reference plane, the hit is projected into the
// reference camera and the plane's features + alpha are bilinearly gathered (zero padding,
// align_corners = False); the planes are then over-composited in index order (0 = back) with
// the reference composer's rules.
//
// One work item per (target pixel, target) loops over the planes and channels.
//
// Per-target camera block (TARGET_STRIDE reals), built on the host: M = R_ref R_c^T
// (row-major; maps a target camera-space direction to reference camera space), a = R_ref C_c +
// t_ref (the target centre in reference camera space), then fx, fy, cx, cy of the target.
// In reference camera space the plane normal is e_z, so the reference's
// tau = (d + n.(C_ref - C_c)) / (n.r + 1e-7) becomes (d - a_z) / (b_z + 1e-7) with b = M r.

#define TARGET_STRIDE 16
#define ALPHA_EPS ((REAL)1e-6)

// Bilinear taps (Taps, make_taps, gather, gather_grad, scatter) and atomic_add_real come
// from the engine's common.cl, which prefixes every program.

// ---- geometry --------------------------------------------------------------------------------

typedef struct {
  REAL ax, ay, az; // target centre in reference camera space
  REAL bx, by, bz; // unit ray direction in reference camera space
} Ray;

// The unit ray of target pixel (x, y) (centre grid): the reference back-projects the pixel at
// depth 1, subtracts the centre and normalises.
inline Ray target_ray(__global const REAL* cam, const int x, const int y, const int ht,
                      const int wt) {
  const REAL u = ((REAL)x + (REAL)0.5) / (REAL)wt, v = ((REAL)y + (REAL)0.5) / (REAL)ht;
  const REAL qx = (u - cam[14]) / cam[12], qy = (v - cam[15]) / cam[13];
  const REAL inv = 1 / sqrt(qx * qx + qy * qy + 1);
  Ray r;
  r.bx = (cam[0] * qx + cam[1] * qy + cam[2]) * inv;
  r.by = (cam[3] * qx + cam[4] * qy + cam[5]) * inv;
  r.bz = (cam[6] * qx + cam[7] * qy + cam[8]) * inv;
  r.ax = cam[9];
  r.ay = cam[10];
  r.az = cam[11];
  return r;
}

// Taps (in the h x w reference image) of the hit of ray r with the plane at depth d.
inline void plane_taps(const Ray* r, const REAL d, const REAL rfx, const REAL rfy, const REAL rcx,
                       const REAL rcy, const int h, const int w, Taps* t) {
  const REAL tau = (d - r->az) / (r->bz + (REAL)1e-7);
  const REAL X = r->ax + tau * r->bx, Y = r->ay + tau * r->by, Z = r->az + tau * r->bz;
  const REAL eps = (REAL)1e-6;
  const REAL zc = Z >= 0 ? max(Z, eps) : min(Z, -eps);
  const REAL u = rfx * (X / zc) + rcx, v = rfy * (Y / zc) + rcy;
  // A ray parallel to the planes gives an infinite or NaN hit: make_taps rejects it.
  make_taps(2 * u - 1, 2 * v - 1, h, w, t);
}

// ---- rendering -------------------------------------------------------------------------------

// mpi [P, C1, h, w] (C1 - 1 feature channels + alpha last), depths [P], targets [N] blocks ->
// out [N, C1 + P, ht, wt] = [colour (C1 - 1) | opacity | weight per plane].
// Items over (x, y, target). Planes are visited front (P - 1) to back (0), accumulating the
// transmittance T_p = prod_{q > p} (1 - a_q + 1e-6); the back plane comes last, when the sum of
// all clamped alphas (which decides whether it is forced opaque) is known.
__kernel void mpi_render_forward(const int P, const int C1, const int h, const int w,
                                 const int N, const int ht, const int wt,
                                 __global const REAL* targets, const REAL rfx, const REAL rfy,
                                 const REAL rcx, const REAL rcy, __global const REAL* depths,
                                 __global const REAL* mpi, __global REAL* out) {
  const int x = get_global_id(0), y = get_global_id(1), n = get_global_id(2);
  if (x >= wt || y >= ht || n >= N) return;
  const int C = C1 - 1, hw = h * w, hwt = ht * wt, pix = y * wt + x;
  __global REAL* o = out + n * (C1 + P) * hwt + pix;
  const Ray r = target_ray(targets + n * TARGET_STRIDE, x, y, ht, wt);
  for (int c = 0; c < C; ++c)
    o[c * hwt] = 0;
  REAL T = 1, sum = 0;
  for (int p = P - 1; p >= 0; --p) {
    Taps t;
    plane_taps(&r, depths[p], rfx, rfy, rcx, rcy, h, w, &t);
    __global const REAL* plane = mpi + p * C1 * hw;
    REAL a = clamp(gather(plane + C * hw, &t), (REAL)0, (REAL)1);
    sum += a;
    // Back plane: opaque where any plane has alpha (the reference's masked background),
    // otherwise 0, so rays that miss the MPI stay empty.
    if (p == 0) a = sum > ALPHA_EPS ? (REAL)1 : (REAL)0;
    const REAL wp = a * T;
    o[(C1 + p) * hwt] = wp;
    if (wp != 0)
      for (int c = 0; c < C; ++c)
        o[c * hwt] += wp * gather(plane + c * hw, &t);
    T *= 1 - a + ALPHA_EPS;
  }
  o[C * hwt] = 1 - T;
}

// Gradient of mpi_render_forward with respect to the MPI (scattered into gmpi, zeroed by the
// host). With e_q = 1 - a_q + 1e-6, T_p = prod_{q>p} e_q, A_p = prod_{q<p} e_q, w_p = a_p T_p,
// G_p = g_weight_p + sum_c g_colour_c f_pc and B_p = sum_{r<p} G_r a_r prod_{r<q<p} e_q:
//   d L / d a_p = T_p (G_p - B_p + g_opacity A_p),   d L / d f_pc = g_colour_c w_p,
// which needs no division by e_p. A front-to-back pass stores T_p in `trans` [N, P, ht, wt];
// a back-to-front pass accumulates A and B. The forced back plane and the clamp (outside
// [0, 1]) pass no gradient to the gathered alpha (PyTorch's clamp passes it at the bounds).
__kernel void mpi_render_backward(const int P, const int C1, const int h, const int w,
                                  const int N, const int ht, const int wt,
                                  __global const REAL* targets, const REAL rfx, const REAL rfy,
                                  const REAL rcx, const REAL rcy, __global const REAL* depths,
                                  __global const REAL* mpi, __global const REAL* g,
                                  __global REAL* trans, __global REAL* gmpi) {
  const int x = get_global_id(0), y = get_global_id(1), n = get_global_id(2);
  if (x >= wt || y >= ht || n >= N) return;
  const int C = C1 - 1, hw = h * w, hwt = ht * wt, pix = y * wt + x;
  __global const REAL* go = g + n * (C1 + P) * hwt + pix;
  __global REAL* tr = trans + n * P * hwt + pix;
  const Ray r = target_ray(targets + n * TARGET_STRIDE, x, y, ht, wt);
  REAL T = 1, sum = 0;
  for (int p = P - 1; p >= 0; --p) {
    Taps t;
    plane_taps(&r, depths[p], rfx, rfy, rcx, rcy, h, w, &t);
    const REAL a = clamp(gather(mpi + (p * C1 + C) * hw, &t), (REAL)0, (REAL)1);
    sum += a;
    tr[p * hwt] = T;
    T *= 1 - a + ALPHA_EPS;
  }
  const REAL back = sum > ALPHA_EPS ? (REAL)1 : (REAL)0;
  const REAL gop = go[C * hwt];
  REAL A = 1, B = 0;
  for (int p = 0; p < P; ++p) {
    Taps t;
    plane_taps(&r, depths[p], rfx, rfy, rcx, rcy, h, w, &t);
    const int base = p * C1 * hw;
    const REAL alpha = gather(mpi + base + C * hw, &t);
    const REAL a = p == 0 ? back : clamp(alpha, (REAL)0, (REAL)1);
    const REAL Tp = tr[p * hwt];
    const REAL wp = a * Tp;
    REAL G = go[(C1 + p) * hwt];
    for (int c = 0; c < C; ++c) {
      const REAL gc = go[c * hwt];
      G += gc * gather(mpi + base + c * hw, &t);
      scatter(gmpi + base + c * hw, &t, gc * wp);
    }
    if (p > 0 && alpha >= 0 && alpha <= 1)
      scatter(gmpi + base + C * hw, &t, Tp * (G - B + gop * A));
    const REAL e = 1 - a + ALPHA_EPS;
    B = B * e + G * a;
    A *= e;
  }
}

// The edge rasteriser and the resolve of ComputeCaustics (steps 3 and 4;
// see caustics.h for the method and caustics_kernels.h for the buffer).
#include <cstdint>
#include <cstring>

#include "render/caustics_kernels.h"

namespace ripple::render::caustics_internal {
namespace {

// Per lane, the weight an edge p0 -> p1 of weight w puts in C: w when it is
// nearer horizontal than vertical (|du| > |dv|), else 0.
RIPPLE_INLINE F8 CWeight(F8 u0, F8 v0, F8 u1, F8 v1, F8 w) {
  return Abs(u1 - u0) > Abs(v1 - v0) ? w : F8{};
}

// Eight mesh edges p0 -> p1 (one per lane, masked by `valid`), each adding w
// times its signed area to the right within each texel row (R) or, when
// nearer horizontal, -w times its signed area above within each texel
// column (C). Either way a row (column) piece of an edge spans at most two
// columns (rows): it is split at the column boundary and both parts are
// deposited by their mean position, branch-free, in three texels.
// Requires 0 <= u <= width - 1 and 0 <= v <= height - 1 on active lanes.
RIPPLE_INLINE void Edges8(F8 u0, F8 v0, F8 u1, F8 v1, F8 w, I8 valid,
                          AccumBuffer* buf) {
  const F8 zero = {}, one = Bc(1.0f);
  const I8 in_c = Abs(u1 - u0) > Abs(v1 - v0);
  // Rasteriser frame: rows along y (major), pieces along x (minor).
  F8 x0 = in_c ? v0 : u0, y0 = in_c ? u0 : v0;
  F8 x1 = in_c ? v1 : u1, y1 = in_c ? u1 : v1;
  const F8 wk = in_c ? -w : w;
  const I8 flip = y0 > y1;
  const F8 sx = x0, sy = y0;
  x0 = flip ? x1 : x0;
  y0 = flip ? y1 : y0;
  x1 = flip ? sx : x1;
  y1 = flip ? sy : y1;
  const F8 dir = flip ? -wk : wk;
  const F8 ext = y1 - y0;
  const I8 active = valid & (w != zero) & (ext > zero);
  const F8 dxdy = (x1 - x0) / (active ? ext : one);
  const F8 adxdy = Abs(dxdy);
  // Weight per unit of x extent (unused when dx = 0).
  const I8 slanted = adxdy > zero;
  const F8 ds = slanted ? dir / (slanted ? adxdy : one) : zero;
  // All coordinates are >= 0 on active lanes, so truncation is floor.
  const I8 yb = ToI(y0);
  const I8 t1 = ToI(y1);
  const I8 ye = t1 - (ToF(t1) < y1);  // ceil(y1)
  const I8 n = active ? ye - yb : I8{};
  const int stride = buf->stride;
  const I8 major = in_c ? Bci(1) : Bci(stride);
  const I8 minor = in_c ? Bci(stride) : Bci(1);
  const I8 base =
      (in_c ? Bci(static_cast<std::int32_t>(buf->plane)) : I8{}) + yb * major;
  const I8 dummy = Bci(static_cast<std::int32_t>(buf->dummy())) + Lanes() * 4;
  alignas(32) std::int32_t nn[kLanes];
  std::memcpy(nn, &n, sizeof(nn));
  int kmax = 0;
  for (int l = 0; l < kLanes; ++l) kmax = std::max(kmax, nn[l]);
  const F8 ybf = ToF(yb);
  float* data = buf->data.data();
  for (int k = 0; k < kmax; ++k) {
    const F8 yk = ybf + static_cast<float>(k);
    const F8 ylo = Max(yk, y0), yhi = Min(yk + one, y1);
    const F8 dy = yhi - ylo;
    const F8 x = x0 + dxdy * (ylo - y0);
    const F8 xnext = x + dxdy * dy;
    const F8 d = dy * dir;
    const F8 xa = Min(x, xnext), xb = Max(x, xnext);
    const I8 xa_i = ToI(xa);
    const F8 xa_floor = ToF(xa_i);
    const F8 bx = xa_floor + one;
    const F8 xm = Min(xb, bx);
    const F8 d_left = xb > bx ? ds * (xm - xa) : d;
    const F8 d_right = d - d_left;
    const F8 f_left = 0.5f * (xa + xm) - xa_floor;
    const F8 f_right = 0.5f * (xb - xm);
    const I8 on = n > Bci(k);
    const I8 idx = on ? base + k * major + xa_i * minor : dummy;
    const I8 step = on ? minor : Bci(1);
    alignas(32) std::int32_t ii[kLanes], ss[kLanes];
    alignas(32) float a0[kLanes], a1[kLanes], a2[kLanes];
    const F8 b0 = d_left - d_left * f_left;
    const F8 b1 = d_left * f_left + d_right - d_right * f_right;
    const F8 b2 = d_right * f_right;
    std::memcpy(ii, &idx, sizeof(ii));
    std::memcpy(ss, &step, sizeof(ss));
    std::memcpy(a0, &b0, sizeof(a0));
    std::memcpy(a1, &b1, sizeof(a1));
    std::memcpy(a2, &b2, sizeof(a2));
    for (int l = 0; l < kLanes; ++l) {
      float* p = data + ii[l];
      const int s = ss[l];
      p[0] += a0[l];
      p[s] += a1[l];
      p[2 * s] += a2[l];
    }
  }
}

// 3. Each mesh edge once, weighted by the difference of the two triangles
//    it separates (their opposite traversals cancel in the rest), and each
//    corner's Q term. Corner rows j0..j1 own the edges leaving their
//    corners: H (i, j) -> (i + 1, j), V (i, j) -> (i, j + 1) and the
//    diagonal D (i, j) -> (i + 1, j + 1).
//
//    Why C and Q: with R(e) the signed area right of edge e = p0 -> p1 (the
//    font-rs term) and C(e) the signed area above it, R(e) + C(e) =
//    Q(p0) - Q(p1), Q(p) being the quadrant x > p.x, y > p.y. So an edge
//    nearer horizontal adds -w C(e) to C and +w, -w to its ends' Q, whose
//    texel coverage is separable: a 2 x 2 bilinear deposit in a plane
//    prefix-summed along both axes. Every edge then spans at most two
//    texels per row (column) piece, the case that vectorises.
RIPPLE_INLINE void EdgesRowsImpl(const Ctx& c, AccumBuffer* buf, int j_begin,
                                 int j_end) {
  const int cx = c.cx;
  const float* u = c.u;
  const float* v = c.v;
  const float* w0 = c.w0;
  const float* w1 = c.w1;
  const int stride = buf->stride;
  const I8 dummy = Bci(static_cast<std::int32_t>(buf->dummy())) + Lanes() * 4;
  const I8 q_base = Bci(static_cast<std::int32_t>(2 * buf->plane));
  float* data = buf->data.data();
  for (int j = j_begin; j < j_end; ++j) {
    const std::ptrdiff_t o = static_cast<std::ptrdiff_t>(j) * cx;
    for (int i = 0; i < cx; i += kLanes) {
      const I8 valid = (Lanes() + i) < Bci(cx);
      const std::ptrdiff_t a = o + i;
      const F8 ua = Load(u + a), va = Load(v + a);
      const F8 ub = Load(u + a + 1), vb = Load(v + a + 1);            // H end
      const F8 ud = Load(u + a + cx), vd = Load(v + a + cx);          // V end
      const F8 uc = Load(u + a + cx + 1), vc = Load(v + a + cx + 1);  // D
      const F8 w0_here = Load(w0 + c.wi(i, j));
      const F8 w1_here = Load(w1 + c.wi(i, j));
      const F8 w0_left = Load(w0 + c.wi(i - 1, j));
      const F8 w1_left_below = Load(w1 + c.wi(i - 1, j - 1));
      const F8 w0_left_below = Load(w0 + c.wi(i - 1, j - 1));
      const F8 w1_below = Load(w1 + c.wi(i, j - 1));
      // H: T0 of (i, j) above, T1 of (i, j - 1) below; V: T0 of (i - 1, j)
      // left, T1 of (i, j) right; D: T1 of (i, j) left, T0 right.
      const F8 wh = w0_here - w1_below;
      const F8 wv = w0_left - w1_here;
      const F8 wd = w1_here - w0_here;
      Edges8(ua, va, ub, vb, wh, valid, buf);
      Edges8(ua, va, ud, vd, wv, valid, buf);
      Edges8(ua, va, uc, vc, wd, valid, buf);
      // Q of corner (i, j): + the C weights of the edges leaving it, - those
      // of the edges arriving (H from the left, V from below, D from
      // below-left).
      const F8 ul = Load(u + a - 1), vl = Load(v + a - 1);
      const F8 ubl = Load(u + a - cx), vbl = Load(v + a - cx);
      const F8 ull = Load(u + a - cx - 1), vll = Load(v + a - cx - 1);
      const F8 wh_in = w0_left - w1_left_below;
      const F8 wv_in = w0_left_below - w1_below;
      const F8 wd_in = w1_left_below - w0_left_below;
      const F8 q =
          CWeight(ua, va, ub, vb, wh) + CWeight(ua, va, ud, vd, wv) +
          CWeight(ua, va, uc, vc, wd) - CWeight(ul, vl, ua, va, wh_in) -
          CWeight(ubl, vbl, ua, va, wv_in) - CWeight(ull, vll, ua, va, wd_in);
      const I8 on = valid & (q != F8{});
      const I8 iu = ToI(ua), iv = ToI(va);
      const F8 fu = ua - ToF(iu), fv = va - ToF(iv);
      const I8 idx = on ? q_base + iv * stride + iu : dummy;
      const I8 step = on ? Bci(stride) : Bci(1);
      const F8 gu = 1.0f - fu, gv = 1.0f - fv;
      const F8 b00 = q * gu * gv, b10 = q * fu * gv;
      const F8 b01 = q * gu * fv, b11 = q * fu * fv;
      alignas(32) std::int32_t ii[kLanes], ss[kLanes];
      alignas(32) float q00[kLanes], q10[kLanes], q01[kLanes], q11[kLanes];
      std::memcpy(ii, &idx, sizeof(ii));
      std::memcpy(ss, &step, sizeof(ss));
      std::memcpy(q00, &b00, sizeof(q00));
      std::memcpy(q10, &b10, sizeof(q10));
      std::memcpy(q01, &b01, sizeof(q01));
      std::memcpy(q11, &b11, sizeof(q11));
      for (int l = 0; l < kLanes; ++l) {
        float* p = data + ii[l];
        const int s = ss[l];
        p[0] += q00[l];
        p[1] += q10[l];
        p[s] += q01[l];
        p[s + 1] += q11[l];
      }
    }
  }
}

// Lane shuffles: GCC's __builtin_shuffle takes an index vector, clang's
// __builtin_shufflevector the indices themselves (clang builds the
// sanitizer and fuzzing configuration).
#if defined(__clang__)
#define RIPPLE_SHUFFLE2(a, b, ...) __builtin_shufflevector(a, b, __VA_ARGS__)
#else
#define RIPPLE_SHUFFLE2(a, b, ...) __builtin_shuffle(a, b, I8{__VA_ARGS__})
#endif

// Inclusive prefix sum of the eight lanes.
RIPPLE_INLINE F8 Scan8(F8 x) {
  const F8 z = {};
  x += RIPPLE_SHUFFLE2(z, x, 0, 8, 9, 10, 11, 12, 13, 14);
  x += RIPPLE_SHUFFLE2(z, x, 0, 1, 8, 9, 10, 11, 12, 13);
  x += RIPPLE_SHUFFLE2(z, x, 0, 1, 2, 3, 8, 9, 10, 11);
  return x;
}

// 4. AccumBuffer rows 0..y_last: texel coverage = Sx(R + Sy(Q)) + Sy(C),
// written
//    into `out` (rows of `stride` floats) for rows y_first..y_last; the
//    column sums of C and Q run in col_c, col_q (stride floats, zeroed).
RIPPLE_INLINE void ResolveImpl(AccumBuffer* buf, int y_first, int y_last,
                               float* col_c, float* col_q, float* out) {
  const int stride = buf->stride;
  for (int y = 0; y < y_last; ++y) {
    const size_t o = static_cast<size_t>(y) * stride;
    const float* r = buf->r() + o;
    const float* cc = buf->c() + o;
    const float* qq = buf->q() + o;
    if (y < y_first) {
      for (int x = 0; x < stride; x += kLanes) {
        Store(col_c + x, Load(col_c + x) + Load(cc + x));
        Store(col_q + x, Load(col_q + x) + Load(qq + x));
      }
      continue;
    }
    float* row = out + static_cast<size_t>(y - y_first) * stride;
    F8 carry = {};
    for (int x = 0; x < stride; x += kLanes) {
      const F8 sc = Load(col_c + x) + Load(cc + x);
      const F8 sq = Load(col_q + x) + Load(qq + x);
      Store(col_c + x, sc);
      Store(col_q + x, sq);
      const F8 s = Scan8(Load(r + x) + sq) + carry;
      carry = RIPPLE_SHUFFLE2(s, s, 7, 7, 7, 7, 7, 7, 7, 7);  // last lane
      Store(row + x, s + sc);
    }
  }
}

}  // namespace

RIPPLE_CAUSTICS_KERNEL(EdgesRows,
                       (const Ctx& c, AccumBuffer* buf, int j0, int j1),
                       (c, buf, j0, j1))
RIPPLE_CAUSTICS_KERNEL(Resolve,
                       (AccumBuffer * buf, int y_first, int y_last,
                        float* col_c, float* col_q, float* out),
                       (buf, y_first, y_last, col_c, col_q, out))

}  // namespace ripple::render::caustics_internal

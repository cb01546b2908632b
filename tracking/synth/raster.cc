#include "tracking/synth/raster.h"

#include <algorithm>
#include <cmath>

namespace ripple::synth {
namespace {

// Clips `in` (n vertices) against the half-plane sign*(coord - bound) <= 0
// along axis `axis`; writes to `out` and returns its size.
int ClipAxis(const Eigen::Vector2d* in, int n, int axis, double bound,
             double sign, Eigen::Vector2d* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = in[i];
    const Eigen::Vector2d& b = in[(i + 1) % n];
    const double da = sign * (a[axis] - bound);
    const double db = sign * (b[axis] - bound);
    if (da <= 0) out[m++] = a;
    if ((da < 0 && db > 0) || (da > 0 && db < 0)) {
      const double t = da / (da - db);
      out[m++] = a + t * (b - a);
    }
  }
  return m;
}

double ShoelaceArea(const Eigen::Vector2d* p, int n) {
  double a = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& u = p[i];
    const Eigen::Vector2d& v = p[(i + 1) % n];
    a += u.x() * v.y() - v.x() * u.y();
  }
  return 0.5 * a;
}

}  // namespace

// Clips a convex quad to [x0, x1] x [y0, y1]; the result (at most 8
// vertices) is written to `out` and its size returned (< 3: empty).
static int ClipQuadToRect(const Eigen::Vector2d quad[4], double x0, double y0,
                          double x1, double y1, Eigen::Vector2d out[8]) {
  Eigen::Vector2d tmp[8];
  int n = 4;
  for (int i = 0; i < 4; ++i) out[i] = quad[i];
  n = ClipAxis(out, n, 0, x0, -1, tmp);
  if (n < 3) return 0;
  n = ClipAxis(tmp, n, 0, x1, +1, out);
  if (n < 3) return 0;
  n = ClipAxis(out, n, 1, y0, -1, tmp);
  if (n < 3) return 0;
  return ClipAxis(tmp, n, 1, y1, +1, out);
}

double QuadRectArea(const Eigen::Vector2d quad[4], double x0, double y0,
                    double x1, double y1) {
  double qx0 = quad[0].x(), qx1 = qx0, qy0 = quad[0].y(), qy1 = qy0;
  for (int i = 1; i < 4; ++i) {
    qx0 = std::min(qx0, quad[i].x());
    qx1 = std::max(qx1, quad[i].x());
    qy0 = std::min(qy0, quad[i].y());
    qy1 = std::max(qy1, quad[i].y());
  }
  if (qx1 <= x0 || qx0 >= x1 || qy1 <= y0 || qy0 >= y1) return 0.0;
  if (qx0 >= x0 && qx1 <= x1 && qy0 >= y0 && qy1 <= y1)
    return std::abs(ShoelaceArea(quad, 4));
  Eigen::Vector2d clipped[8];
  const int n = ClipQuadToRect(quad, x0, y0, x1, y1, clipped);
  return n < 3 ? 0.0 : std::abs(ShoelaceArea(clipped, n));
}

double QuadRectMappedArea(const Eigen::Vector2d quad[4], double x0, double y0,
                          double x1, double y1, const Eigen::Matrix3d& h) {
  Eigen::Vector2d clipped[8];
  const int n = ClipQuadToRect(quad, x0, y0, x1, y1, clipped);
  if (n < 3) return 0.0;
  for (int i = 0; i < n; ++i)
    clipped[i] = (h * clipped[i].homogeneous()).hnormalized();
  return std::abs(ShoelaceArea(clipped, n));
}

double PolygonArea(const std::vector<Eigen::Vector2d>& polygon) {
  return ShoelaceArea(polygon.data(), static_cast<int>(polygon.size()));
}

std::vector<Eigen::Vector2d> ClipToRect(
    const std::vector<Eigen::Vector2d>& poly, double x0, double y0, double x1,
    double y1) {
  std::vector<Eigen::Vector2d> a = poly, b(2 * poly.size() + 8);
  auto clip = [&](int axis, double bound, double sign) {
    b.resize(2 * a.size() + 8);
    const int m = ClipAxis(a.data(), static_cast<int>(a.size()), axis, bound,
                           sign, b.data());
    b.resize(m);
    std::swap(a, b);
  };
  clip(0, x0, -1);
  if (a.size() >= 3) clip(0, x1, +1);
  if (a.size() >= 3) clip(1, y0, -1);
  if (a.size() >= 3) clip(1, y1, +1);
  if (a.size() < 3) a.clear();
  return a;
}

bool RasterizePolygon(const std::vector<Eigen::Vector2d>& polygon_px, int width,
                      int height, cv::Mat* coverage, cv::Rect* roi) {
  if (polygon_px.size() < 3) return false;
  // Work in "cell" coordinates where pixel u spans [u, u+1] (shift +0.5), and
  // clip to one cell beyond the image so nothing outside can leak in.
  std::vector<Eigen::Vector2d> shifted(polygon_px.size());
  for (size_t i = 0; i < polygon_px.size(); ++i)
    shifted[i] = polygon_px[i] + Eigen::Vector2d(0.5, 0.5);
  const std::vector<Eigen::Vector2d> poly =
      ClipToRect(shifted, -1.0, -1.0, width + 1.0, height + 1.0);
  if (poly.size() < 3) return false;
  double minx = 1e300, maxx = -1e300, miny = 1e300, maxy = -1e300;
  for (const auto& p : poly) {
    minx = std::min(minx, p.x());
    maxx = std::max(maxx, p.x());
    miny = std::min(miny, p.y());
    maxy = std::max(maxy, p.y());
  }
  // Local accumulation buffer with origin at (ox, oy), one spare column.
  const int ox = static_cast<int>(std::floor(minx));
  const int oy = static_cast<int>(std::floor(miny));
  const int w = static_cast<int>(std::ceil(maxx)) - ox + 2;
  const int h = static_cast<int>(std::ceil(maxy)) - oy;
  if (w <= 0 || h <= 0) return false;
  std::vector<double> acc(size_t(w) * h + 2, 0.0);
  auto add = [&](int row, int col, double v) {
    acc[size_t(row) * w + col] += v;
  };
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    Eigen::Vector2d p0 = poly[i] - Eigen::Vector2d(ox, oy);
    Eigen::Vector2d p1 = poly[(i + 1) % n] - Eigen::Vector2d(ox, oy);
    if (p0.y() == p1.y()) continue;
    double dir = 1.0;
    if (p0.y() > p1.y()) {
      std::swap(p0, p1);
      dir = -1.0;
    }
    const double dxdy = (p1.x() - p0.x()) / (p1.y() - p0.y());
    double x = p0.x();
    const int y_begin = std::max(0, static_cast<int>(std::floor(p0.y())));
    const int y_end = std::min(h, static_cast<int>(std::ceil(p1.y())));
    if (p0.y() < 0) x -= p0.y() * dxdy;
    for (int y = y_begin; y < y_end; ++y) {
      const double dy =
          std::min(double(y + 1), p1.y()) - std::max(double(y), p0.y());
      const double xnext = x + dxdy * dy;
      const double d = dy * dir;
      const double xa = std::min(x, xnext), xb = std::max(x, xnext);
      const double xa_floor = std::floor(xa);
      const int xa_i = static_cast<int>(xa_floor);
      const double xb_ceil = std::ceil(xb);
      const int xb_i = static_cast<int>(xb_ceil);
      if (xb_i <= xa_i + 1) {
        // The segment stays within one cell column: trapezoid split.
        const double xmf = 0.5 * (x + xnext) - xa_floor;
        add(y, xa_i, d - d * xmf);
        add(y, xa_i + 1, d * xmf);
      } else {
        const double s = 1.0 / (xb - xa);
        const double xa_f = xa - xa_floor;
        const double a0 = 0.5 * s * (1 - xa_f) * (1 - xa_f);
        const double xb_f = xb - xb_ceil + 1.0;
        const double am = 0.5 * s * xb_f * xb_f;
        add(y, xa_i, d * a0);
        if (xb_i == xa_i + 2) {
          add(y, xa_i + 1, d * (1 - a0 - am));
        } else {
          const double a1 = s * (1.5 - xa_f);
          add(y, xa_i + 1, d * (a1 - a0));
          for (int xi = xa_i + 2; xi < xb_i - 1; ++xi) add(y, xi, d * s);
          const double a2 = a1 + (xb_i - xa_i - 3) * s;
          add(y, xb_i - 1, d * (1 - a2 - am));
        }
        add(y, xb_i, d * am);
      }
      x = xnext;
    }
  }
  // Prefix sums along rows give the signed covered area of each cell.
  const cv::Rect local(ox, oy, w, h);
  const cv::Rect image(0, 0, width, height);
  *roi = local & image;
  if (roi->empty()) return false;
  coverage->create(roi->height, roi->width, CV_32F);
  for (int y = 0; y < h; ++y) {
    const int iy = oy + y;
    double sum = 0;
    for (int x = 0; x < w; ++x) {
      sum += acc[size_t(y) * w + x];
      const int ix = ox + x;
      if (iy >= roi->y && iy < roi->br().y && ix >= roi->x && ix < roi->br().x)
        coverage->at<float>(iy - roi->y, ix - roi->x) =
            static_cast<float>(std::min(1.0, std::abs(sum)));
    }
  }
  return true;
}

}  // namespace ripple::synth

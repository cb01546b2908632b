#include "geometry/camera_model.h"

#include <Eigen/LU>
#include <cmath>

namespace ripple::geometry {

bool ParseTransfer(const std::string& name, Transfer* transfer) {
  if (name == "srgb") {
    *transfer = Transfer::kSrgb;
  } else if (name == "linear") {
    *transfer = Transfer::kLinear;
  } else {
    return false;
  }
  return true;
}

const char* TransferName(Transfer transfer) {
  return transfer == Transfer::kSrgb ? "srgb" : "linear";
}

Eigen::Vector2d CameraModel::ProjectWithJacobian(
    const Eigen::Vector3d& p, Eigen::Matrix<double, 2, 3>* j) const {
  const double iz = 1.0 / p.z();
  const double x = p.x() * iz, y = p.y() * iz;
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double num = 1 + dist[0] * r2 + dist[1] * r4 + dist[4] * r6;
  const double den = 1 + dist[5] * r2 + dist[6] * r4 + dist[7] * r6;
  const double radial = num / den;
  // d radial / d r2
  const double dnum = dist[0] + 2 * dist[1] * r2 + 3 * dist[4] * r4;
  const double dden = dist[5] + 2 * dist[6] * r2 + 3 * dist[7] * r4;
  const double dr = (dnum * den - num * dden) / (den * den);
  const double p1 = dist[2], p2 = dist[3];
  const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
  const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
  // d (xd, yd) / d (x, y)
  const double a = radial + 2 * x * x * dr + 2 * p1 * y + 6 * p2 * x;
  const double b = 2 * x * y * dr + 2 * p1 * x + 2 * p2 * y;
  const double d = radial + 2 * y * y * dr + 6 * p1 * y + 2 * p2 * x;
  // d (x, y) / d p = [iz, 0, -x iz; 0, iz, -y iz]
  (*j) << fx * a * iz, fx * b * iz, -fx * (a * x + b * y) * iz,  //
      fy * b * iz, fy * d * iz, -fy * (b * x + d * y) * iz;
  return {fx * xd + cx, fy * yd + cy};
}

bool CameraModel::HasDistortion() const {
  for (double d : dist) {
    if (d != 0.0) return true;
  }
  return false;
}

bool CameraModel::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (width <= 0 || height <= 0)
    return fail("image_width/image_height must be positive");
  if (!(std::isfinite(fx) && std::isfinite(fy) && fx > 0 && fy > 0))
    return fail("camera_matrix: focal lengths must be positive and finite");
  if (!(std::isfinite(cx) && std::isfinite(cy)))
    return fail("camera_matrix: principal point must be finite");
  for (double d : dist) {
    if (!std::isfinite(d))
      return fail("distortion_coefficients: values must be finite");
  }
  return true;
}

Eigen::Vector2d CameraModel::UndistortToNormalized(
    const Eigen::Vector2d& pixel) const {
  const Eigen::Vector2d target((pixel.x() - cx) / fx, (pixel.y() - cy) / fy);
  if (!HasDistortion()) return target;
  // Newton iterations on the forward model with a numeric Jacobian; converges
  // in a handful of steps for any lens OpenCV's model describes well.
  Eigen::Vector2d p = target;
  for (int it = 0; it < 20; ++it) {
    auto f = [&](const Eigen::Vector2d& q) {
      const Eigen::Vector2d px = DistortNormalized(q.x(), q.y());
      return Eigen::Vector2d((px.x() - cx) / fx, (px.y() - cy) / fy);
    };
    const Eigen::Vector2d r = f(p) - target;
    if (r.norm() < 1e-14) break;
    const double h = 1e-7;
    Eigen::Matrix2d j;
    j.col(0) = (f(p + Eigen::Vector2d(h, 0)) - f(p)) / h;
    j.col(1) = (f(p + Eigen::Vector2d(0, h)) - f(p)) / h;
    p -= j.inverse() * r;
  }
  return p;
}

CameraModel CameraModel::Scaled(int new_width, int new_height) const {
  CameraModel c = *this;
  const double sx = double(new_width) / width, sy = double(new_height) / height;
  c.width = new_width;
  c.height = new_height;
  c.fx *= sx;
  c.fy *= sy;
  // Pixel centres: the continuous image edge is at -0.5, so scale about it.
  c.cx = (cx + 0.5) * sx - 0.5;
  c.cy = (cy + 0.5) * sy - 0.5;
  return c;
}

CameraModel MakeIdealCamera(int width, int height, double hfov_deg) {
  CameraModel c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width / std::tan(0.5 * hfov_deg * M_PI / 180.0);
  c.cx = 0.5 * width - 0.5;
  c.cy = 0.5 * height - 0.5;
  return c;
}

}  // namespace ripple::geometry

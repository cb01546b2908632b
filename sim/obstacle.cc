#include "sim/obstacle.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace ripple::sim {
namespace {

bool Positive(double v) { return std::isfinite(v) && v > 0; }

}  // namespace

bool VoxelVolume::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (nx <= 0 || ny <= 0 || nz <= 0 || nx > 4096 || ny > 4096 || nz > 4096)
    return fail("voxel dimensions must be in [1, 4096]");
  if (static_cast<double>(nx) * ny * nz > 1 << 28)
    return fail("voxel volume larger than 2^28 voxels");
  if (!Positive(voxel_size_m)) return fail("voxel size must be positive");
  if (occupied.size() != static_cast<size_t>(nx) * ny * nz)
    return fail("voxel occupancy size does not match nx*ny*nz");
  return true;
}

bool LoadVoxelVolume(const std::string& path, double voxel_size_m,
                     VoxelVolume* volume, std::string* error) {
  auto fail = [&](const std::string& m) {
    if (error) *error = path + ": " + m;
    return false;
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return fail("cannot open voxel file (not a regular file)");
  const uintmax_t file_bytes = std::filesystem::file_size(path, ec);
  if (ec) return fail("cannot open voxel file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot open voxel file");
  // The file is streamed: the header is checked before the body is read,
  // and the body is never held as text.
  int ch = 0;
  auto next = [&]() {  // the next character outside comments, or EOF
    ch = in.get();
    if (ch == '#')
      while (ch != EOF && ch != '\n') ch = in.get();
    return ch;
  };
  auto token = [&](std::string* out) {  // whitespace-separated, <= 32 chars
    out->clear();
    while (next() != EOF && std::isspace(ch)) {
    }
    while (ch != EOF && !std::isspace(ch) && out->size() < 32) {
      out->push_back(static_cast<char>(ch));
      next();
    }
    return !out->empty();
  };
  auto integer = [&](int* out) {
    std::string t;
    if (!token(&t) || t.size() > 9 ||
        t.find_first_not_of("0123456789") != std::string::npos)
      return false;
    *out = std::stoi(t);
    return true;
  };
  std::string magic;
  int version = 0;
  VoxelVolume v;
  if (!token(&magic) || magic != "ripple-voxels" || !integer(&version))
    return fail("not a voxel file (expected 'ripple-voxels 1')");
  if (version != 1)
    return fail("unsupported voxel file version " + std::to_string(version));
  if (!integer(&v.nx) || !integer(&v.ny) || !integer(&v.nz))
    return fail("missing dimensions nx ny nz");
  v.voxel_size_m = voxel_size_m;
  if (v.nx <= 0 || v.ny <= 0 || v.nz <= 0 || v.nx > 4096 || v.ny > 4096 ||
      v.nz > 4096 || static_cast<double>(v.nx) * v.ny * v.nz > (1 << 28))
    return fail("voxel dimensions out of range");
  const size_t n = static_cast<size_t>(v.nx) * v.ny * v.nz;
  // One character per voxel, a newline per row and comments: a file much
  // larger than that is not this volume (and would take long to scan).
  if (file_bytes > 4 * static_cast<uintmax_t>(n) + (1u << 20))
    return fail(std::to_string(file_bytes) + " bytes, far more than " +
                std::to_string(n) + " voxels need");
  if (file_bytes < n)
    return fail("expected " + std::to_string(n) + " voxels in a file of " +
                std::to_string(file_bytes) + " bytes");
  v.occupied.reserve(n);
  while (next() != EOF) {
    if (ch == '0' || ch == '1') {
      if (v.occupied.size() == n) return fail("more voxels than nx*ny*nz");
      v.occupied.push_back(ch == '1');
    } else if (!std::isspace(ch)) {
      return fail("unexpected character code " + std::to_string(ch));
    }
  }
  if (v.occupied.size() != n)
    return fail("expected " + std::to_string(n) + " voxels, found " +
                std::to_string(v.occupied.size()));
  std::string why;
  if (!v.IsValid(&why)) return fail(why);
  *volume = std::move(v);
  return true;
}

bool SaveVoxelVolume(const VoxelVolume& volume, const std::string& path,
                     std::string* error) {
  std::string why;
  if (!volume.IsValid(&why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  std::ofstream out(path);
  if (!out) {
    if (error) *error = path + ": cannot write voxel file";
    return false;
  }
  out << "ripple-voxels 1\n"
      << volume.nx << ' ' << volume.ny << ' ' << volume.nz << '\n';
  for (int c = 0; c < volume.nz; ++c) {
    out << "# z layer " << c << '\n';
    for (int b = 0; b < volume.ny; ++b) {
      for (int a = 0; a < volume.nx; ++a)
        out << (volume.At(a, b, c) ? '1' : '0');
      out << '\n';
    }
  }
  if (!out) {
    if (error) *error = path + ": write failed";
    return false;
  }
  return true;
}

bool Obstacle::IsValid(std::string* error) const {
  auto fail = [&](const std::string& m) {
    if (error) *error = m;
    return false;
  };
  if (!tank_from_obstacle.IsFinite())
    return fail("obstacle pose must be finite");
  switch (shape) {
    case Shape::kBox:
      for (double s : box_size_m)
        if (!Positive(s)) return fail("box size must be positive");
      return true;
    case Shape::kCylinder:
      if (!Positive(radius_m)) return fail("cylinder radius must be positive");
      if (!Positive(height_m)) return fail("cylinder height must be positive");
      return true;
    case Shape::kVoxels:
      if (!voxels) return fail("voxel obstacle without a volume");
      return voxels->IsValid(error);
  }
  return fail("unknown obstacle shape");
}

bool Obstacle::ContainsInObstacle(const std::array<double, 3>& p) const {
  switch (shape) {
    case Shape::kBox:
      return std::abs(p[0]) <= 0.5 * box_size_m[0] &&
             std::abs(p[1]) <= 0.5 * box_size_m[1] &&
             std::abs(p[2]) <= 0.5 * box_size_m[2];
    case Shape::kCylinder:
      return p[2] >= 0 && p[2] <= height_m &&
             p[0] * p[0] + p[1] * p[1] <= radius_m * radius_m;
    case Shape::kVoxels: {
      const VoxelVolume& v = *voxels;
      const double s = v.voxel_size_m;
      const double fa = std::floor(p[0] / s + 0.5 * v.nx);
      const double fb = std::floor(p[1] / s + 0.5 * v.ny);
      const double fc = std::floor(p[2] / s);
      if (!(fa >= 0 && fa < v.nx && fb >= 0 && fb < v.ny && fc >= 0 &&
            fc < v.nz))
        return false;
      return v.At(static_cast<int>(fa), static_cast<int>(fb),
                  static_cast<int>(fc));
    }
  }
  return false;
}

bool Obstacle::ContainsInTank(const std::array<double, 3>& p_in_tank) const {
  return ContainsInObstacle(tank_from_obstacle.Inverse().Apply(p_in_tank));
}

std::array<std::array<double, 3>, 2> Obstacle::LocalBounds() const {
  switch (shape) {
    case Shape::kBox:
      return {
          {{-0.5 * box_size_m[0], -0.5 * box_size_m[1], -0.5 * box_size_m[2]},
           {0.5 * box_size_m[0], 0.5 * box_size_m[1], 0.5 * box_size_m[2]}}};
    case Shape::kCylinder:
      return {{{-radius_m, -radius_m, 0}, {radius_m, radius_m, height_m}}};
    case Shape::kVoxels: {
      const VoxelVolume& v = *voxels;
      const double s = v.voxel_size_m;
      return {{{-0.5 * v.nx * s, -0.5 * v.ny * s, 0},
               {0.5 * v.nx * s, 0.5 * v.ny * s, v.nz * s}}};
    }
  }
  return {};
}

}  // namespace ripple::sim

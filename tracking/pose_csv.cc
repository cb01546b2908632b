#include "tracking/pose_csv.h"

#include <cmath>
#include <fstream>
#include <sstream>

namespace ripple::tracking {

const char kPoseCsvHeader[] =
    "frame,time_s,object,status,tx,ty,tz,qw,qx,qy,qz,tip_x,tip_y,tip_z,faces,"
    "reproj_rmse_px,ms";

std::string FormatPoseRow(const PoseRow& row) {
  char buf[512];
  std::string out;
  std::snprintf(buf, sizeof(buf), "%d,%.6f,%s,%s", row.frame, row.time_s,
                row.object.c_str(), ToString(row.status));
  out += buf;
  if (row.cam_from_object) {
    const Pose& p = *row.cam_from_object;
    const Eigen::Quaterniond q = p.CanonicalRotation().normalized();
    std::snprintf(buf, sizeof(buf), ",%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f",
                  p.translation.x(), p.translation.y(), p.translation.z(),
                  q.w(), q.x(), q.y(), q.z());
    out += buf;
  } else {
    out += ",,,,,,,";
  }
  if (row.tip_in_tank) {
    std::snprintf(buf, sizeof(buf), ",%.9f,%.9f,%.9f", row.tip_in_tank->x(),
                  row.tip_in_tank->y(), row.tip_in_tank->z());
    out += buf;
  } else {
    out += ",,,";
  }
  out += ",";
  for (size_t i = 0; i < row.faces.size(); ++i) {
    if (i) out += ";";
    out += std::to_string(row.faces[i]);
  }
  std::snprintf(buf, sizeof(buf), ",%.4f,%.4f", row.reproj_rmse_px, row.ms);
  out += buf;
  return out;
}

PoseCsvWriter::~PoseCsvWriter() { Close(); }

bool PoseCsvWriter::Open(const std::string& path, std::string* error) {
  Close();
  file_ = std::fopen(path.c_str(), "w");
  if (!file_) {
    if (error) *error = "cannot write pose file '" + path + "'";
    return false;
  }
  std::fprintf(file_, "%s\n", kPoseCsvHeader);
  return std::ferror(file_) == 0;
}

bool PoseCsvWriter::Write(const PoseRow& row) {
  if (!file_) return false;
  std::fprintf(file_, "%s\n", FormatPoseRow(row).c_str());
  std::fflush(file_);
  return std::ferror(file_) == 0;
}

bool PoseCsvWriter::Close() {
  if (!file_) return true;
  const bool ok = std::ferror(file_) == 0;
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  return ok && closed;
}

namespace {

std::vector<std::string> SplitComma(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream ss(line);
  while (std::getline(ss, cell, ',')) out.push_back(cell);
  if (!line.empty() && line.back() == ',') out.push_back("");
  return out;
}

bool ParseDouble(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(*out);
}

}  // namespace

std::optional<std::vector<PoseRow>> ReadPoseCsv(const std::string& path,
                                                std::string* error) {
  std::ifstream in(path);
  auto fail =
      [&](int line,
          const std::string& what) -> std::optional<std::vector<PoseRow>> {
    if (error)
      *error = "pose file '" + path + "'" +
               (line > 0 ? " line " + std::to_string(line) : "") + ": " + what;
    return std::nullopt;
  };
  if (!in) return fail(0, "cannot open file");
  std::string line;
  if (!std::getline(in, line)) return fail(1, "empty file");
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != kPoseCsvHeader) return fail(1, "unexpected header");
  std::vector<PoseRow> rows;
  int n = 1;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::vector<std::string> c = SplitComma(line);
    if (c.size() != 17) return fail(n, "expected 17 columns");
    PoseRow r;
    double v;
    // In int range before the conversion (1e300 would overflow it).
    if (!ParseDouble(c[0], &v) || v != std::floor(v) || v < 0 || v > 1e9)
      return fail(n, "column 'frame' is not a frame index");
    r.frame = static_cast<int>(v);
    if (!ParseDouble(c[1], &r.time_s)) return fail(n, "column 'time_s'");
    r.object = c[2];
    if (r.object != "tank" && r.object != "pen")
      return fail(n, "column 'object' must be tank or pen");
    const auto status = ParseTrackStatus(c[3]);
    if (!status) return fail(n, "column 'status' must be tracked/held/lost");
    r.status = *status;
    if (!c[4].empty()) {
      double p[7];
      for (int i = 0; i < 7; ++i)
        if (!ParseDouble(c[4 + i], &p[i])) return fail(n, "pose columns");
      Eigen::Quaterniond q(p[3], p[4], p[5], p[6]);
      if (std::abs(q.norm() - 1.0) > 1e-4)
        return fail(n, "quaternion is not unit length");
      r.cam_from_object = Pose(q.normalized(), {p[0], p[1], p[2]});
    }
    if (!c[11].empty()) {
      double t[3];
      for (int i = 0; i < 3; ++i)
        if (!ParseDouble(c[11 + i], &t[i])) return fail(n, "tip columns");
      r.tip_in_tank = Eigen::Vector3d(t[0], t[1], t[2]);
    }
    if (!c[14].empty()) {
      std::istringstream fs(c[14]);
      std::string id;
      while (std::getline(fs, id, ';')) {
        if (!ParseDouble(id, &v) || v != std::floor(v) || std::abs(v) > 1e9)
          return fail(n, "column 'faces'");
        r.faces.push_back(static_cast<int>(v));
      }
    }
    if (!ParseDouble(c[15], &r.reproj_rmse_px))
      return fail(n, "column 'reproj_rmse_px'");
    if (!ParseDouble(c[16], &r.ms)) return fail(n, "column 'ms'");
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace ripple::tracking

#include "tracking/rig.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/core/persistence.hpp>
#include <set>
#include <sstream>

#include "tracking/tag_family.h"
#include "tracking/yaml_tree.h"

namespace ripple::tracking {
namespace {

// Parse failure carrying the YAML path of the offending field.
struct FieldError {
  std::string field;
  std::string what;
};

double ReadNumber(const YamlNode& parent, const std::string& key,
                  const std::string& path) {
  const YamlNode& n = parent[key];
  if (n.empty()) throw FieldError{path + "." + key, "missing"};
  if (!n.IsNumber()) throw FieldError{path + "." + key, "not a number"};
  const double v = n.Number();
  if (!std::isfinite(v)) throw FieldError{path + "." + key, "not finite"};
  return v;
}

double ReadPositive(const YamlNode& parent, const std::string& key,
                    const std::string& path) {
  const double v = ReadNumber(parent, key, path);
  if (!(v > 0)) throw FieldError{path + "." + key, "must be positive"};
  return v;
}

int ReadInt(const YamlNode& parent, const std::string& key,
            const std::string& path) {
  const double v = ReadNumber(parent, key, path);
  if (v != std::floor(v) || std::abs(v) > 1e9)
    throw FieldError{path + "." + key, "not an integer"};
  return static_cast<int>(v);
}

std::string ReadString(const YamlNode& parent, const std::string& key,
                       const std::string& path) {
  const YamlNode& n = parent[key];
  if (n.empty()) throw FieldError{path + "." + key, "missing"};
  if (n.IsString()) return n.Text();
  throw FieldError{path + "." + key, "not a string"};
}

std::vector<double> ReadVector(const YamlNode& parent, const std::string& key,
                               size_t size, const std::string& path) {
  const YamlNode& n = parent[key];
  if (n.empty()) throw FieldError{path + "." + key, "missing"};
  if (!n.IsSequence() || n.size() != size)
    throw FieldError{path + "." + key,
                     "must be a list of " + std::to_string(size) + " numbers"};
  std::vector<double> out;
  for (const YamlNode& e : n.children()) {
    if (!e.IsNumber() || !std::isfinite(e.Number()))
      throw FieldError{path + "." + key, "must hold finite numbers"};
    out.push_back(e.Number());
  }
  return out;
}

const YamlNode& RequireMap(const YamlNode& n, const std::string& path) {
  if (n.empty()) throw FieldError{path, "missing"};
  if (!n.IsMapping()) throw FieldError{path, "must be a mapping"};
  return n;
}

Pose ReadPose(const YamlNode& node, const std::string& path) {
  const std::vector<double> p = ReadVector(node, "position", 3, path);
  const std::vector<double> q = ReadVector(node, "quaternion", 4, path);
  const double norm =
      std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > 1e-3)
    throw FieldError{path + ".quaternion",
                     "must be a unit quaternion [w, x, y, z] (norm " +
                         std::to_string(norm) + ")"};
  Eigen::Quaterniond rot(q[0], q[1], q[2], q[3]);
  return Pose(rot.normalized(), Eigen::Vector3d(p[0], p[1], p[2]));
}

std::vector<TagPlacement> ReadTags(const YamlNode& parent,
                                   const std::string& key,
                                   const std::string& path) {
  const YamlNode& n = parent[key];
  const std::string here = path + "." + key;
  if (n.empty()) throw FieldError{here, "missing"};
  if (!n.IsSequence() || n.size() == 0)
    throw FieldError{here, "must be a non-empty list of tags"};
  std::vector<TagPlacement> tags;
  int i = 0;
  for (const YamlNode& t : n.children()) {
    const std::string tp = here + "[" + std::to_string(i++) + "]";
    RequireMap(t, tp);
    TagPlacement tag;
    tag.id = ReadInt(t, "id", tp);
    if (tag.id < 0) throw FieldError{tp + ".id", "must be >= 0"};
    tag.edge_m = ReadPositive(t, "edge", tp);
    tag.object_from_tag = ReadPose(t, tp);
    tags.push_back(tag);
  }
  return tags;
}

ObstacleSpec ReadObstacle(const YamlNode& o, const std::string& path,
                          const std::string& rig_dir) {
  RequireMap(o, path);
  ObstacleSpec spec;
  if (!o["name"].empty()) spec.name = ReadString(o, "name", path);
  const std::string shape = ReadString(o, "shape", path);
  const std::string frame = ReadString(o, "frame", path);
  if (frame == "tank") {
    spec.attached_tag = -1;
  } else if (frame.rfind("tag:", 0) == 0) {
    try {
      size_t used = 0;
      spec.attached_tag = std::stoi(frame.substr(4), &used);
      if (used != frame.size() - 4 || spec.attached_tag < 0)
        throw std::invalid_argument("id");
    } catch (const std::exception&) {
      throw FieldError{path + ".frame", "must be 'tank' or 'tag:<id>'"};
    }
  } else {
    throw FieldError{path + ".frame", "must be 'tank' or 'tag:<id>'"};
  }
  spec.parent_from_obstacle = ReadPose(o, path);
  if (shape == "box") {
    spec.shape = ObstacleSpec::Shape::kBox;
    const std::vector<double> s = ReadVector(o, "size", 3, path);
    if (!(s[0] > 0 && s[1] > 0 && s[2] > 0))
      throw FieldError{path + ".size", "must be positive"};
    spec.box_size_m = Eigen::Vector3d(s[0], s[1], s[2]);
  } else if (shape == "cylinder") {
    spec.shape = ObstacleSpec::Shape::kCylinder;
    spec.radius_m = ReadPositive(o, "radius", path);
    spec.height_m = ReadPositive(o, "height", path);
  } else if (shape == "voxels") {
    spec.shape = ObstacleSpec::Shape::kVoxels;
    spec.voxel_file = ReadString(o, "file", path);
    if (!spec.voxel_file.empty() && spec.voxel_file[0] != '/' &&
        !rig_dir.empty())
      spec.voxel_file = rig_dir + "/" + spec.voxel_file;
    spec.voxel_size_m = ReadPositive(o, "voxel_size", path);
  } else {
    throw FieldError{path + ".shape",
                     "unknown shape '" + shape + "' (box, cylinder, voxels)"};
  }
  return spec;
}

void WritePose(cv::FileStorage& fs, const Pose& pose) {
  const Eigen::Quaterniond q = pose.CanonicalRotation();
  fs << "position"
     << "[:" << pose.translation.x() << pose.translation.y()
     << pose.translation.z() << "]";
  fs << "quaternion"
     << "[:" << q.w() << q.x() << q.y() << q.z() << "]";
}

void WriteTags(cv::FileStorage& fs, const std::vector<TagPlacement>& tags) {
  fs << "[";
  for (const TagPlacement& t : tags) {
    fs << "{:"
       << "id" << t.id << "edge" << t.edge_m;
    WritePose(fs, t.object_from_tag);
    fs << "}";
  }
  fs << "]";
}

}  // namespace

double FacingCosine(const Pose& cam_from_object, const Pose& object_from_tag) {
  const Pose cam_from_tag = cam_from_object * object_from_tag;
  const Eigen::Vector3d z = cam_from_tag.R().col(2);  // into the tag
  const Eigen::Vector3d ray = cam_from_tag.translation.normalized();
  return z.dot(ray);
}

Eigen::Vector3d TagPlacement::CornerInObject(int k) const {
  static const double kSign[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const Eigen::Vector3d c_in_tag(0.5 * edge_m * kSign[k][0],
                                 0.5 * edge_m * kSign[k][1], 0.0);
  return object_from_tag * c_in_tag;
}

const TagPlacement* Rig::FindTankTag(int id) const {
  for (const TagPlacement& t : tank_tags)
    if (t.id == id) return &t;
  return nullptr;
}

const TagPlacement* Rig::FindPenFace(int id) const {
  if (!pen) return nullptr;
  for (const TagPlacement& t : pen->faces)
    if (t.id == id) return &t;
  return nullptr;
}

bool IsKnownTagFamily(const std::string& family) {
  static const std::set<std::string> kFamilies = {
      "tag36h11",         "tag25h9",        "tag16h5",
      "tagCircle21h7",    "tagCircle49h12", "tagStandard41h12",
      "tagStandard52h13", "tagCustom48h12"};
  return kFamilies.count(family) > 0;
}

bool Rig::IsValid(std::string* error) const {
  auto fail = [&](const std::string& what) {
    if (error) *error = what;
    return false;
  };
  if (version != kRigVersion)
    return fail("rig_version: unsupported version " + std::to_string(version));
  if (!IsKnownTagFamily(family))
    return fail("tag_family: unknown family '" + family + "'");
  if (tank_tags.empty()) return fail("tank.tags: no tags");
  if (!(tank.size_x_m > 0 && tank.size_y_m > 0))
    return fail("tank.inner_size: must be positive");
  // A tabletop tank. The simulation grid, the caustics map and the shadow
  // maps divide these lengths into a fixed number of cells and the
  // rasterisers turn metres into int pixel indices: kilometre or nanometre
  // tanks overflow them.
  auto out_of = [&](const char* field, double v, double lo, double hi) {
    return fail(std::string(field) + ": " + std::to_string(v) +
                " m is outside [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "] m");
  };
  for (double s : {tank.size_x_m, tank.size_y_m})
    if (!(s >= kMinTankSideM && s <= kMaxTankSideM))
      return out_of("tank.inner_size", s, kMinTankSideM, kMaxTankSideM);
  if (!(tank.wall_height_m > 0))
    return fail("tank.wall_height: must be positive");
  if (!(tank.wall_height_m <= kMaxTankSideM))
    return out_of("tank.wall_height", tank.wall_height_m, 0, kMaxTankSideM);
  if (!(tank.water_level_m > 0 && tank.water_level_m <= tank.wall_height_m))
    return fail("tank.water_level: must be in (0, wall_height]");
  // Ids the family can draw and decode: a larger one is no tag at all.
  const std::unique_ptr<TagFamily> tag_family = TagFamily::Create(family);
  const int num_codes = tag_family ? tag_family->num_codes() : 0;
  auto beyond = [&](const char* where, int id) {
    return fail(std::string(where) + ": tag id " + std::to_string(id) +
                " is beyond " + family + " (ids 0 to " +
                std::to_string(num_codes - 1) + ")");
  };
  std::set<int> ids;
  for (const TagPlacement& t : tank_tags) {
    if (!(t.edge_m > 0)) return fail("tank.tags: edge must be positive");
    if (!(t.edge_m <= kMaxTankSideM))
      return out_of("tank.tags: edge", t.edge_m, 0, kMaxTankSideM);
    if (!(t.object_from_tag.translation.norm() <= kMaxRigReachM))
      return fail("tank.tags: tag " + std::to_string(t.id) + " lies over " +
                  std::to_string(kMaxRigReachM) + " m from the tank centre");
    if (t.id >= num_codes) return beyond("tank.tags", t.id);
    if (!ids.insert(t.id).second)
      return fail("tank.tags: duplicate tag id " + std::to_string(t.id));
  }
  if (pen) {
    if (pen->faces.empty()) return fail("pen.faces: no faces");
    if (!(pen->cube_edge_m > 0)) return fail("pen.cube_edge: must be positive");
    if (!(pen->cube_edge_m <= kMaxTankSideM))
      return out_of("pen.cube_edge", pen->cube_edge_m, 0, kMaxTankSideM);
    if (!(pen->shaft_length_m <= kMaxTankSideM &&
          pen->shaft_radius_m <= kMaxTankSideM &&
          pen->tip_in_pen.norm() <= kMaxRigReachM))
      return fail("pen: shaft and tip must lie within " +
                  std::to_string(kMaxTankSideM) + " m of the cube");
    if (!(pen->shaft_radius_m > 0))
      return fail("pen.shaft_radius: must be positive");
    if (!(pen->shaft_length_m > 0))
      return fail("pen.shaft_length: must be positive");
    for (const TagPlacement& t : pen->faces) {
      if (!(t.edge_m > 0)) return fail("pen.faces: edge must be positive");
      if (t.id >= num_codes) return beyond("pen.faces", t.id);
      if (t.edge_m > pen->cube_edge_m + 1e-9)
        return fail("pen.faces: tag " + std::to_string(t.id) +
                    " is larger than the cube face");
      if (!ids.insert(t.id).second)
        return fail("pen.faces: duplicate tag id " + std::to_string(t.id));
    }
  }
  for (const ObstacleSpec& o : obstacles) {
    const double size = std::max(
        {o.box_size_m.maxCoeff(), o.radius_m, o.height_m, o.voxel_size_m});
    if (!(size <= kMaxTankSideM) ||
        !(o.parent_from_obstacle.translation.norm() <= kMaxRigReachM))
      return fail("obstacles: '" + o.name + "' must be at most " +
                  std::to_string(kMaxTankSideM) + " m large and within " +
                  std::to_string(kMaxRigReachM) + " m of its frame");
    if (o.attached_tag >= 0 && !FindTankTag(o.attached_tag))
      return fail("obstacles: frame tag:" + std::to_string(o.attached_tag) +
                  " is not a tank tag");
  }
  return true;
}

std::optional<Rig> LoadRig(const std::string& path, std::string* error) {
  auto fail = [&](const std::string& what) -> std::optional<Rig> {
    if (error) *error = "rig file '" + path + "': " + what;
    return std::nullopt;
  };
  {
    std::ifstream probe(path);
    if (!probe) return fail("cannot open file");
  }
  const size_t slash = path.find_last_of('/');
  const std::string rig_dir =
      slash == std::string::npos ? std::string() : path.substr(0, slash);
  Rig rig;
  try {
    std::string yaml_error;
    const std::optional<YamlNode> doc =
        LoadYamlFile(path, YamlLimits{}, &yaml_error);
    if (!doc) return fail(yaml_error);
    if (!doc->IsMapping()) return fail("not a YAML mapping of rig fields");
    const YamlNode& root = *doc;
    rig.version = ReadInt(root, "rig_version", "");
    if (rig.version != kRigVersion)
      throw FieldError{".rig_version", "unsupported version " +
                                           std::to_string(rig.version) +
                                           " (this build reads " +
                                           std::to_string(kRigVersion) + ")"};
    rig.family = ReadString(root, "tag_family", "");
    if (!IsKnownTagFamily(rig.family))
      throw FieldError{".tag_family", "unknown family '" + rig.family + "'"};

    const YamlNode& tank = RequireMap(root["tank"], ".tank");
    const std::vector<double> size = ReadVector(tank, "inner_size", 2, ".tank");
    if (!(size[0] > 0 && size[1] > 0))
      throw FieldError{".tank.inner_size", "must be positive"};
    rig.tank.size_x_m = size[0];
    rig.tank.size_y_m = size[1];
    rig.tank.wall_height_m = ReadPositive(tank, "wall_height", ".tank");
    rig.tank.water_level_m = ReadPositive(tank, "water_level", ".tank");
    if (rig.tank.water_level_m > rig.tank.wall_height_m)
      throw FieldError{".tank.water_level", "must not exceed wall_height"};
    rig.tank_tags = ReadTags(tank, "tags", ".tank");

    const YamlNode& pen = root["pen"];
    if (!pen.empty()) {
      RequireMap(pen, ".pen");
      PenSpec spec;
      spec.cube_edge_m = ReadPositive(pen, "cube_edge", ".pen");
      const std::vector<double> tip = ReadVector(pen, "tip", 3, ".pen");
      spec.tip_in_pen = Eigen::Vector3d(tip[0], tip[1], tip[2]);
      spec.shaft_radius_m = ReadPositive(pen, "shaft_radius", ".pen");
      spec.shaft_length_m = ReadPositive(pen, "shaft_length", ".pen");
      spec.faces = ReadTags(pen, "faces", ".pen");
      rig.pen = spec;
    }

    const YamlNode& obstacles = root["obstacles"];
    if (!obstacles.empty()) {
      if (!obstacles.IsSequence())
        throw FieldError{".obstacles", "must be a list"};
      int i = 0;
      for (const YamlNode& o : obstacles.children())
        rig.obstacles.push_back(ReadObstacle(
            o, ".obstacles[" + std::to_string(i++) + "]", rig_dir));
    }
  } catch (const FieldError& e) {
    const std::string field =
        e.field.empty() || e.field[0] != '.' ? e.field : e.field.substr(1);
    return fail("field '" + field + "': " + e.what);
  } catch (const std::exception& e) {
    // std::bad_alloc and the like: the file is named, the program goes on.
    return fail(std::string("cannot be read: ") + e.what());
  }
  std::string why;
  if (!rig.IsValid(&why)) return fail(why);
  return rig;
}

bool SaveRig(const Rig& rig, const std::string& path, std::string* error) {
  try {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    if (!fs.isOpened()) {
      if (error) *error = "cannot write rig file '" + path + "'";
      return false;
    }
    fs << "rig_version" << rig.version;
    fs << "tag_family" << rig.family;
    fs << "tank"
       << "{";
    fs << "inner_size"
       << "[:" << rig.tank.size_x_m << rig.tank.size_y_m << "]";
    fs << "wall_height" << rig.tank.wall_height_m;
    fs << "water_level" << rig.tank.water_level_m;
    fs << "tags";
    WriteTags(fs, rig.tank_tags);
    fs << "}";
    if (rig.pen) {
      fs << "pen"
         << "{";
      fs << "cube_edge" << rig.pen->cube_edge_m;
      fs << "tip"
         << "[:" << rig.pen->tip_in_pen.x() << rig.pen->tip_in_pen.y()
         << rig.pen->tip_in_pen.z() << "]";
      fs << "shaft_radius" << rig.pen->shaft_radius_m;
      fs << "shaft_length" << rig.pen->shaft_length_m;
      fs << "faces";
      WriteTags(fs, rig.pen->faces);
      fs << "}";
    }
    if (!rig.obstacles.empty()) {
      fs << "obstacles"
         << "[";
      for (const ObstacleSpec& o : rig.obstacles) {
        fs << "{";
        if (!o.name.empty()) fs << "name" << o.name;
        fs << "frame"
           << (o.attached_tag < 0 ? std::string("tank")
                                  : "tag:" + std::to_string(o.attached_tag));
        WritePose(fs, o.parent_from_obstacle);
        switch (o.shape) {
          case ObstacleSpec::Shape::kBox:
            fs << "shape"
               << "box";
            fs << "size"
               << "[:" << o.box_size_m.x() << o.box_size_m.y()
               << o.box_size_m.z() << "]";
            break;
          case ObstacleSpec::Shape::kCylinder:
            fs << "shape"
               << "cylinder"
               << "radius" << o.radius_m << "height" << o.height_m;
            break;
          case ObstacleSpec::Shape::kVoxels:
            fs << "shape"
               << "voxels"
               << "file" << o.voxel_file << "voxel_size" << o.voxel_size_m;
            break;
        }
        fs << "}";
      }
      fs << "]";
    }
    fs.release();
  } catch (const cv::Exception& e) {
    if (error) *error = "cannot write rig file '" + path + "': " + e.err;
    return false;
  }
  return true;
}

}  // namespace ripple::tracking

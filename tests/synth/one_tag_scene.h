// The synth tests' shared scene: one big tag36h11 tag at the tank origin
// seen by a small pinhole camera, and the black share of a flat-lit pixel.
#ifndef RIPPLE_TESTS_SYNTH_ONE_TAG_SCENE_H_
#define RIPPLE_TESTS_SYNTH_ONE_TAG_SCENE_H_

#include <opencv2/core.hpp>

#include "tracking/camera.h"
#include "tracking/rig.h"
#include "tracking/synth/floor_pattern.h"

namespace ripple::synth::testing {

// One tag (id 0, `edge` metres) at the tank origin, image axes as DESIGN.md.
inline tracking::Rig OneTagRig(double edge) {
  tracking::Rig rig;
  rig.family = "tag36h11";
  rig.tank = {0.3, 0.3, 0.05, 0.03};
  tracking::TagPlacement tag;
  tag.id = 0;
  tag.edge_m = edge;
  tag.object_from_tag =
      tracking::Pose(Eigen::Quaterniond(0, 1, 0, 0), Eigen::Vector3d::Zero());
  rig.tank_tags.push_back(tag);
  return rig;
}

inline tracking::Camera TestCamera() {
  tracking::Camera c;
  c.width = 320;
  c.height = 240;
  c.fx = 300.7;
  c.fy = 290.2;
  c.cx = 161.3;
  c.cy = 117.8;
  return c;
}

// Black fraction of a pixel of a flat-lit linear render (paper 0, ink 1).
inline double BlackFraction(const cv::Mat& linear, int u, int v) {
  const cv::Vec3f p = linear.at<cv::Vec3f>(v, u);
  return (kPaperBgr[0] - p[0]) / (kPaperBgr[0] - kInkBgr[0]);
}

}  // namespace ripple::synth::testing

#endif  // RIPPLE_TESTS_SYNTH_ONE_TAG_SCENE_H_

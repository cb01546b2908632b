// The "before" column of `ripple bench render`: renders the scenes that
// `ripple bench render --export DIR` wrote with the renderer of an earlier
// commit (its own library, built from a checkout of it) and prints the mean
// LDR-FLIP inside the water against the exported reference. Not part of the
// build:
//
//   git worktree add /tmp/prev 8ccd885
//   cmake -S /tmp/prev -B /tmp/prev/build -DCMAKE_BUILD_TYPE=Release
//   cmake --build /tmp/prev/build -j2 --target ripple
//   g++ -O2 -std=c++17 -DRIPPLE_FLIP_H='"bench/flip.h"' -I/tmp/prev -I. \
//     -I/usr/include/opencv4 -I/usr/include/eigen3 \
//     scripts/render_bench_previous.cc bench/flip.cc -o /tmp/previous \
//     /tmp/prev/build/render/libripple_render.a \
//     /tmp/prev/build/geometry/libripple_geometry.a -lopencv_core \
//     -lopencv_imgcodecs -lopencv_imgproc -lEGL -lOSMesa -lglfw -lpthread -ldl
//   /tmp/previous DIR flat ring demo_a demo_b demo_c tiles pen grazing lens
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "render/context.h"
#include "render/renderer.h"
#include RIPPLE_FLIP_H
using namespace ripple;
static std::vector<double> Nums(const std::string& s, const std::string& key) {
  std::vector<double> v;
  size_t p = s.find(key);
  if (p == std::string::npos) return v;
  p = s.find('[', p);
  size_t e = s.find(']', p);
  std::stringstream ss(s.substr(p + 1, e - p - 1));
  std::string t;
  while (std::getline(ss, t, ',')) v.push_back(std::stod(t));
  return v;
}
static double Num(const std::string& s, const std::string& key) {
  size_t p = s.find(key);
  if (p == std::string::npos) return 0;
  return std::stod(s.substr(p + key.size()));
}
static glm::dmat4 Mat(const std::vector<double>& v) {
  glm::dmat4 m(1.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = v[r * 4 + c];
  return m;
}
int main(int argc, char** argv) {
  std::string dir = argv[1];
  std::vector<std::string> names(argv + 2, argv + argc);
  auto ctx =
      render::Context::TryCreate(render::Backend::kEgl, 640, 480, nullptr);
  for (const std::string& n : names) {
    std::string d = dir + "/" + n;
    std::ifstream f(d + "/scene.yml");
    std::stringstream b;
    b << f.rdbuf();
    std::string y = b.str();
    cv::FileStorage cs(d + "/camera.yml", cv::FileStorage::READ);
    cv::Mat K, D;
    cs["camera_matrix"] >> K;
    cs["distortion_coefficients"] >> D;
    render::Intrinsics k;
    k.width = (int)cs["image_width"];
    k.height = (int)cs["image_height"];
    k.fx = K.at<double>(0, 0);
    k.fy = K.at<double>(1, 1);
    k.cx = K.at<double>(0, 2);
    k.cy = K.at<double>(1, 2);
    for (int i = 0; i < (int)D.total(); ++i) k.dist[i] = D.at<double>(i);
    render::RendererOptions ro;
    auto r = render::Renderer::TryCreate(ctx.get(), k, ro, nullptr);
    render::SceneInputs in;
    in.cam_from_tank = Mat(Nums(y, "cam_from_tank:"));
    in.tank.size_x = Num(y, "size_x: ");
    in.tank.size_y = Num(y, "size_y: ");
    in.tank.wall_height = Num(y, "wall_height: ");
    in.tank.water_level = Num(y, "water_level: ");
    auto l = Nums(y, "towards:");
    in.light_in_tank = {l[0], l[1], l[2]};
    std::vector<float> h;
    if (y.find("heights: {file") != std::string::npos) {
      int nx = (int)Num(y, "nx: "), ny = (int)Num(y, "ny: ");
      float cell = Num(y, "cell_size: ");
      std::ifstream hf(d + "/heights.npy", std::ios::binary);
      std::string all((std::istreambuf_iterator<char>(hf)), {});
      size_t hl = (unsigned char)all[8] | ((unsigned char)all[9] << 8);
      h.resize(size_t(nx) * ny);
      memcpy(h.data(), all.data() + 10 + hl, h.size() * 4);
      in.water = {h.data(), nx, ny, cell, 1};
    }
    in.pen_visible = y.find("visible: true") != std::string::npos;
    in.pen.cube_edge = Num(y, "cube_edge: ");
    in.pen.shaft_radius = Num(y, "shaft_radius: ");
    in.pen.shaft_length = Num(y, "shaft_length: ");
    in.tank_from_pen = Mat(Nums(y, "tank_from_pen:"));
    size_t p = y.find("obstacles:");
    while ((p = y.find("- {shape: ", p)) != std::string::npos) {
      render::Obstacle o;
      o.shape = y.compare(p + 10, 3, "box") == 0
                    ? render::Obstacle::Shape::kBox
                    : render::Obstacle::Shape::kCylinder;
      auto sz = Nums(y.substr(p), "size:");
      o.size = {sz[0], sz[1], sz[2]};
      o.tank_from_obstacle = Mat(Nums(y.substr(p), "tank_from_obstacle:"));
      in.obstacles.push_back(o);
      p += 10;
    }
    cv::Mat video = cv::imread(d + "/video.png");
    in.video = {video.data, video.cols, video.rows, (int)video.step};
    cv::Mat out(k.height, k.width, CV_8UC3);
    r->Render(in);
    r->ReadBgr(out.data, out.step);
    cv::imwrite(d + "/realtime_old.png", out);
    cv::Mat ref = cv::imread(d + "/reference.png"), fmap;
    std::string err;
    bench::ComputeFlip({}, ref, out, &fmap, &err);
    // water mask from the new renderer's run: pixels the mask file marks
    cv::Mat mask(k.height, k.width, CV_8U, cv::Scalar(0));
    const glm::dmat4 tfc = glm::inverse(in.cam_from_tank);
    const glm::dvec3 eye(tfc[3]);
    for (int v = 0; v < k.height; ++v)
      for (int u = 0; u < k.width; ++u) {
        glm::dvec3 dd(
            tfc * glm::dvec4((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0, 0.0));
        if (dd.z >= -1e-9) continue;
        double s = (in.tank.water_level - eye.z) / dd.z;
        glm::dvec3 q = eye + s * dd;
        if (s > 0 && std::abs(q.x) < 0.5 * in.tank.size_x &&
            std::abs(q.y) < 0.5 * in.tank.size_y)
          mask.at<uchar>(v, u) = 255;
      }
    std::printf("%-8s old-renderer FLIP %.4f\n", n.c_str(),
                bench::MeanFlip(fmap, mask));
  }
}

#include "app/app_live_session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace ripple::app {
namespace {

constexpr int kHudFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kHudScale = 0.45;
constexpr int kHudLineHeightPx = 18;
constexpr int kHudMarginPx = 8;  // left and right of the text

int TextWidthPx(const std::string& text) {
  int baseline = 0;
  return cv::getTextSize(text, kHudFont, kHudScale, 1, &baseline).width;
}

std::string KeyName(int key) {
  if (key == ' ') return "space";
  if (key == 27) return "Esc";
  return std::string(1, static_cast<char>(key));
}

const char* OnOff(bool on) { return on ? "on" : "off"; }

}  // namespace

std::vector<std::string> FitHudLines(const std::vector<std::string>& lines,
                                     int max_width_px) {
  const int room = max_width_px - 2 * kHudMarginPx;
  std::vector<std::string> fitted;
  for (const std::string& line : lines) {
    if (TextWidthPx(line) <= room) {
      fitted.push_back(line);
      continue;
    }
    // Greedy: as many words per line as fit; continuation lines indented.
    std::string current;
    size_t pos = 0;
    while (pos < line.size()) {
      size_t end = line.find(' ', pos);
      if (end == std::string::npos) end = line.size();
      const std::string word = line.substr(pos, end - pos);
      pos = end + 1;
      if (word.empty()) continue;
      const std::string candidate =
          current.empty() ? word : current + " " + word;
      if (!current.empty() && TextWidthPx(candidate) > room) {
        fitted.push_back(current);
        current = "  " + word;
      } else {
        current = candidate;
      }
    }
    if (!current.empty()) fitted.push_back(current);
  }
  return fitted;
}

cv::Mat DrawHud(const std::vector<std::string>& lines, int max_width_px) {
  const std::vector<std::string> fitted = FitHudLines(lines, max_width_px);
  int widest = 0;
  for (const std::string& line : fitted)
    widest = std::max(widest, TextWidthPx(line));
  const int width = std::min(max_width_px, widest + 2 * kHudMarginPx);
  cv::Mat hud(static_cast<int>(fitted.size()) * kHudLineHeightPx + 10,
              std::max(width, 1), CV_8UC4, cv::Scalar(0, 0, 0, 150));
  for (size_t i = 0; i < fitted.size(); ++i)
    cv::putText(
        hud, fitted[i], cv::Point(kHudMarginPx, 18 + int(i) * kHudLineHeightPx),
        kHudFont, kHudScale, cv::Scalar(255, 255, 255, 255), 1, cv::LINE_AA);
  return hud;
}

LiveSession::LiveSession(const LiveSessionOptions& options, Pipeline* pipeline,
                         RawSink* raw)
    : options_(options), pipeline_(pipeline), raw_(raw) {
  BuildKeyTable();
}

void LiveSession::BuildKeyTable() {
  using W = sim::WaterModelOptions;
  keys_ = {
      {{'h'}, "this help", [this](int) { help_ = !help_; }},
      {{'v', 'V'},
       "viscosity down/up",
       [this](int key) {
         ChangeWater([key](W* w) {
           if (w->waves == sim::WaveModel::kPaper) {
             double& v = w->paper.viscosity_per_s;
             v = key == 'v' ? v / 1.5 : std::max(0.1, v * 1.5);
           } else {
             // Half a decade a press: water 1e-6 to honey 1e-2 in eight.
             double& nu = w->spectral.physics.kinematic_viscosity_m2_per_s;
             nu = key == 'v'
                      ? nu / std::sqrt(10.0)
                      : std::min(1.0, std::max(1e-7, nu * std::sqrt(10.0)));
           }
         });
       }},
      {{'r', 'R'},
       "radius down/up",
       [this](int key) {
         ChangeWater([key](W* w) {
           const double f = key == 'r' ? 1 / 1.25 : 1.25;
           w->paper.pen_radius_m *= f;
           w->spectral.pen_radius_m *= f;
         });
       }},
      {{'f', 'F'},
       "force down/up",
       [this](int key) {
         ChangeWater([key](W* w) {
           const double f = key == 'f' ? 1 / 1.5 : 1.5;
           w->paper.pen_strength_m_per_s2 *= f;
           w->spectral.pen_strength_m_per_s2 *= f;
           w->spectral.pen_pressure_coefficient =
               std::min(100.0, w->spectral.pen_pressure_coefficient * f);
         });
       }},
      {{'c'},
       "caustics on/off",
       [this](int) {
         pipeline_->effects().caustics = !pipeline_->effects().caustics;
       }},
      {{'s'},
       "shadows on/off",
       [this](int) {
         pipeline_->effects().shadows = !pipeline_->effects().shadows;
       }},
      {{'e'},
       "reflection on/off",
       [this](int) {
         pipeline_->effects().reflection = !pipeline_->effects().reflection;
       }},
      {{'t'},
       "refraction on/off",
       [this](int) {
         pipeline_->effects().refraction = !pipeline_->effects().refraction;
       }},
      {{'o', 'O'},
       "add/remove obstacle",
       [this](int key) {
         if (key == 'o') {
           AddObstacle();
         } else {
           status_line_ = pipeline_->RemoveLastObstacle() ? "obstacle removed"
                                                          : "no obstacle";
         }
       }},
      {{'w'},
       "reset the water",
       [this](int) {
         pipeline_->water().Reset();
         status_line_ = "water reset";
       }},
      {{'p'}, "screenshot (PNG)", [this](int) { Screenshot(); }},
      {{'m'}, "record composite MP4", [this](int) { ToggleVideo(); }},
      {{'k'}, "record raw camera", [this](int) { ToggleRaw(); }},
      {{' '}, "pause", [this](int) { paused_ = !paused_; }},
      {{'q', 27}, "quit", [this](int) { quit_ = true; }},
  };
}

std::vector<std::string> LiveSession::HelpLines() const {
  std::vector<std::string> lines;
  for (const KeyBinding& b : keys_) {
    std::string label;
    for (int key : b.keys) label += (label.empty() ? "" : "/") + KeyName(key);
    lines.push_back(label + "  " + b.help);
  }
  return lines;
}

bool LiveSession::HandleKey(int key) {
  for (const KeyBinding& b : keys_) {
    if (std::find(b.keys.begin(), b.keys.end(), key) == b.keys.end()) continue;
    b.action(key);
    return true;
  }
  return false;
}

void LiveSession::ChangeWater(
    const std::function<void(sim::WaterModelOptions*)>& change) {
  sim::WaterModelOptions w = pipeline_->water().options();
  change(&w);
  std::string error;
  if (!pipeline_->water().SetOptions(w, &error)) status_line_ = error;
}

void LiveSession::AddObstacle() {
  // At the pen tip if it is in the tank, else somewhere inside.
  double x_m, y_m;
  if (last_.tracking.tip_in_tank) {
    x_m = last_.tracking.tip_in_tank->x();
    y_m = last_.tracking.tip_in_tank->y();
  } else {
    std::uniform_real_distribution<double> u(-0.35, 0.35);
    x_m = u(rng_) * pipeline_->rig().tank.size_x_m;
    y_m = u(rng_) * pipeline_->rig().tank.size_y_m;
  }
  std::string error;
  status_line_ =
      pipeline_->AddObstacleAt(x_m, y_m, &error) ? "obstacle added" : error;
}

void LiveSession::Screenshot() {
  // What the window shows now, paused or not.
  cv::Mat shot(options_.frame_size, CV_8UC3);
  pipeline_->renderer().ReadBgr(shot.data, static_cast<int>(shot.step));
  const std::string path =
      options_.out_dir + "/ripple_shot_" + std::to_string(shots_++) + ".png";
  status_line_ =
      cv::imwrite(path, shot) ? "saved " + path : "cannot write " + path;
}

void LiveSession::ToggleVideo() {
  if (video_.is_open()) {
    LoopStop stop;
    status_line_ =
        video_.Close(&stop) ? "composite recording stopped" : stop.message;
    return;
  }
  const std::string path =
      options_.out_dir + "/ripple_live_" + std::to_string(videos_++) + ".mp4";
  std::string error;
  status_line_ = video_.Open(path, options_.fps, options_.frame_size, &error)
                     ? "recording " + path
                     : error;
}

void LiveSession::ToggleRaw() {
  RawRecorder& raw = raw_->recorder();
  if (raw.is_open()) {
    status_line_ =
        "raw recording stopped (" + std::to_string(raw.frames()) + " frames)";
    raw.Close();
    return;
  }
  const std::string dir =
      options_.out_dir + "/ripple_raw_" + std::to_string(raws_++);
  std::string error;
  status_line_ = raw.Open(dir, &error) ? "recording raw to " + dir : error;
}

bool LiveSession::Consume(const LoopFrame& frame, LoopStop*) {
  const FrameReport& r = *frame.report;
  if (!r.rendered) {
    const cv::Mat& bgr = frame.input->bgr;
    pipeline_->renderer().RenderVideoOnly(
        {bgr.data, bgr.cols, bgr.rows, static_cast<int>(bgr.step)});
  }
  table_.Add(r.times);
  frame_times_s_.push_back(frame.input->time_s);
  if (frame_times_s_.size() > static_cast<size_t>(options_.hud_frames))
    frame_times_s_.erase(frame_times_s_.begin());
  last_ = r;
  return true;
}

std::vector<std::string> LiveSession::HudLines() const {
  const bench::StageTimes m = table_.RecentMedian(options_.hud_frames);
  const double fps = frame_times_s_.size() > 1 &&
                             frame_times_s_.back() > frame_times_s_.front()
                         ? (frame_times_s_.size() - 1) /
                               (frame_times_s_.back() - frame_times_s_.front())
                         : 0.0;
  const sim::WaterModelOptions& w = pipeline_->water().options();
  const render::Effects& fx = pipeline_->effects();
  char buf[256];
  std::vector<std::string> lines;
  const Eigen::Vector3d& l = last_.light_in_tank;
  std::snprintf(buf, sizeof(buf),
                "%.1f fps%s   tank %s   pen %s   light %.0f/%.0f deg %s", fps,
                paused_ ? " (paused)" : "",
                tracking::ToString(last_.tracking.tank.status),
                tracking::ToString(last_.tracking.pen.status),
                std::atan2(l.y(), l.x()) * 180 / M_PI,
                std::asin(std::clamp(l.z(), -1.0, 1.0)) * 180 / M_PI,
                last_.light_fixed         ? "(fixed)"
                : last_.light_from_shadow ? "(shadow)"
                                          : "(default)");
  lines.push_back(buf);
  std::snprintf(buf, sizeof(buf),
                "ms  cap %.1f det %.1f pose %.1f occ %.1f sim %.1f caus %.1f "
                "shad %.1f drw %.1f tot %.1f lat %.1f",
                m.cap, m.det, m.pose, m.occ, m.sim, m.caustics, m.shadow, m.drw,
                m.total, m.lat);
  lines.push_back(buf);
  if (w.waves == sim::WaveModel::kPaper) {
    std::snprintf(
        buf, sizeof(buf),
        "paper: damping %.2f/s  radius %.1f mm  force %.1f m/s2  obstacles %d",
        w.paper.viscosity_per_s, 1e3 * w.paper.pen_radius_m,
        w.paper.pen_strength_m_per_s2, pipeline_->num_obstacles());
  } else {
    const sim::SpectralWaterOptions& c = w.spectral;
    std::snprintf(buf, sizeof(buf),
                  "nu %.1e m2/s  radius %.1f mm  %s x%.2f  obstacles %d",
                  c.physics.kinematic_viscosity_m2_per_s, 1e3 * c.pen_radius_m,
                  c.pen == sim::PenModel::kPaperPush ? "push" : "pressure",
                  c.pen == sim::PenModel::kPaperPush
                      ? c.pen_strength_m_per_s2
                      : c.pen_pressure_coefficient,
                  pipeline_->num_obstacles());
  }
  lines.push_back(buf);
  std::snprintf(buf, sizeof(buf),
                "caustics %s shadows %s reflection %s refraction %s%s%s",
                OnOff(fx.caustics), OnOff(fx.shadows), OnOff(fx.reflection),
                OnOff(fx.refraction), video_.is_open() ? "  REC mp4" : "",
                raw_->recorder().is_open() ? "  REC raw" : "");
  lines.push_back(buf);
  if (!status_line_.empty()) lines.push_back(status_line_);
  if (help_) {
    for (const std::string& h : HelpLines()) lines.push_back(h);
  } else {
    lines.push_back("h: keys");
  }
  return lines;
}

void LiveSession::UpdateHud() {
  if (hud_drawn_ && hud_clock_.ElapsedS() < options_.hud_period_s) return;
  hud_clock_.Restart();
  hud_drawn_ = true;
  const cv::Mat hud = DrawHud(HudLines(), options_.frame_size.width);
  pipeline_->renderer().SetOverlay(hud.data, hud.cols, hud.rows,
                                   static_cast<int>(hud.step));
}

bool LiveSession::Turn(LoopStop*) {
  UpdateHud();
  pipeline_->renderer().Present();
  for (int key : pipeline_->context().TakeTypedKeys()) HandleKey(key);
  return !quit_ && !pipeline_->context().ShouldClose();
}

FrameLoopHooks LiveSession::Hooks() {
  FrameLoopHooks hooks;
  hooks.paused = [this] { return paused_; };
  hooks.while_paused = [this] { pipeline_->context().PollEvents(); };
  hooks.after_turn = [this](LoopStop* stop) { return Turn(stop); };
  return hooks;
}

std::vector<FrameSink*> LiveSession::Sinks() { return {this, raw_, &video_}; }

}  // namespace ripple::app

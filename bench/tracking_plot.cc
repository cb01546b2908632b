#include "bench/tracking_plot.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "bench/stats.h"

namespace ripple::bench {

bool PlotTipErrorAgainstTime(
    const std::vector<std::unique_ptr<TrackingSetting>>& settings,
    const std::string& title, const std::string& path) {
  // Medians with the benchmark's rounded rank (NaN: never measured).
  auto median = [](const std::vector<double>& v) {
    PercentileOptions options;
    options.rank = PercentileOptions::Rank::kRounded;
    options.empty_value = NAN;
    return Percentile(v, 50, options);
  };
  const int w = 1100, h = 700, left = 70, right = 430, top = 40, bottom = 60;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double x0 = 1e9, x1 = 0, y0 = 1e9, y1 = 0;
  for (const auto& s : settings) {
    const double x = median(s->ms), y = median(s->errors.tip_mm());
    if (!(x > 0) || !(y > 0)) continue;
    x0 = std::min(x0, x), x1 = std::max(x1, x);
    y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  if (!(x1 > 0)) return true;
  x0 = std::log10(x0) - 0.05, x1 = std::log10(x1) + 0.05;
  y0 = std::log10(y0) - 0.05, y1 = std::log10(y1) + 0.05;
  auto px = [&](double x, double y) {
    return cv::Point(
        int(left + (std::log10(x) - x0) / (x1 - x0) * (w - left - right)),
        int(h - bottom -
            (std::log10(y) - y0) / (y1 - y0) * (h - top - bottom)));
  };
  cv::rectangle(img, cv::Point(left, top), cv::Point(w - right, h - bottom),
                cv::Scalar(0, 0, 0));
  for (int e = int(std::floor(x0)); e <= int(std::ceil(x1)); ++e)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (std::log10(v) < x0 || std::log10(v) > x1) continue;
      const cv::Point p = px(v, std::pow(10.0, y0));
      cv::line(img, p, cv::Point(p.x, top), cv::Scalar(220, 220, 220));
      std::ostringstream t;
      t << v;
      cv::putText(img, t.str(), p + cv::Point(-8, 18), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(0, 0, 0));
    }
  for (int e = int(std::floor(y0)); e <= int(std::ceil(y1)); ++e)
    for (double m : {1.0, 2.0, 5.0}) {
      const double v = m * std::pow(10.0, e);
      if (std::log10(v) < y0 || std::log10(v) > y1) continue;
      const cv::Point p = px(std::pow(10.0, x0), v);
      cv::line(img, p, cv::Point(w - right, p.y), cv::Scalar(220, 220, 220));
      std::ostringstream t;
      t << v;
      cv::putText(img, t.str(), p + cv::Point(-40, 4), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(0, 0, 0));
    }
  cv::putText(img, title, cv::Point(left, 25), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "ms per frame (median, log)", cv::Point(left + 200, h - 20),
              cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  cv::putText(img, "tip error mm (median, log)", cv::Point(5, top - 8),
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
              cv::LINE_AA);
  int row = 0;
  for (size_t i = 0; i < settings.size(); ++i) {
    const TrackingSetting& s = *settings[i];
    const double x = median(s.ms), y = median(s.errors.tip_mm());
    const cv::Scalar colour =
        s.baseline != Baseline::kNone
            ? cv::Scalar(0, 0, 220)
            : (s.name.find("[default]") != std::string::npos
                   ? cv::Scalar(0, 160, 0)
                   : cv::Scalar(200, 80, 0));
    const std::string label = std::to_string(i + 1);
    if (x > 0 && y > 0) {
      cv::circle(img, px(x, y), 4, colour, -1, cv::LINE_AA);
      cv::putText(img, label, px(x, y) + cv::Point(5, -4),
                  cv::FONT_HERSHEY_SIMPLEX, 0.35, colour, 1, cv::LINE_AA);
    }
    cv::putText(img, label + ": " + s.name,
                cv::Point(w - right + 10, top + 12 + 16 * row++),
                cv::FONT_HERSHEY_SIMPLEX, 0.38, colour, 1, cv::LINE_AA);
  }
  return cv::imwrite(path, img);
}

}  // namespace ripple::bench

namespace ripple::bench {

bool PlotErrorsOverFrames(const std::vector<int>& frames,
                          const std::vector<FrameErrors>& errors,
                          const std::vector<bool>& pen_in_truth,
                          const PoseErrorSummary& summary,
                          const std::string& title, const std::string& path) {
  const int w = 1200, left = 80, right = 20, top = 65, panel_h = 200, gap = 50;
  const int h = top + 3 * panel_h + 2 * gap + 50;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(img, title, cv::Point(left, 25), cv::FONT_HERSHEY_SIMPLEX, 0.6,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const size_t n = errors.size();
  const double x_span = n > 1 ? double(n - 1) : 1.0;
  auto x_of = [&](size_t i) {
    return int(left + double(i) / x_span * (w - left - right));
  };
  struct Panel {
    const char* label;
    double FrameErrors::*value;
    const std::vector<FrameRange>* still;
    bool pen;
  };
  const Panel panels[3] = {
      {"tank rotation error, deg (log)", &FrameErrors::tank_rot_deg,
       &summary.tank_static, false},
      {"pen rotation error, deg (log)", &FrameErrors::pen_rot_deg,
       &summary.pen_static, true},
      {"tip error, mm (log)", &FrameErrors::tip_mm, &summary.tip_static, true},
  };
  for (int p = 0; p < 3; ++p) {
    const Panel& panel = panels[p];
    const int y_top = top + p * (panel_h + gap), y_bottom = y_top + panel_h;
    // Log range from the data, at least one decade.
    double lo = 1e30, hi = 0;
    for (const FrameErrors& e : errors) {
      const double v = e.*panel.value;
      if (v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
    }
    if (!(hi > 0)) lo = 1e-3, hi = 1;
    double y0 = std::floor(std::log10(lo)), y1 = std::ceil(std::log10(hi));
    if (y1 - y0 < 1) y1 = y0 + 1;
    auto y_of = [&](double v) {
      const double t =
          (std::log10(std::max(v, std::pow(10.0, y0))) - y0) / (y1 - y0);
      return int(y_bottom - t * panel_h);
    };
    for (const FrameRange& r : *panel.still)
      cv::rectangle(img, cv::Point(x_of(r.begin), y_top),
                    cv::Point(x_of(r.end > 0 ? r.end - 1 : 0), y_bottom),
                    cv::Scalar(250, 232, 215), cv::FILLED);
    for (int e = int(y0); e <= int(y1); ++e) {
      const int y = y_of(std::pow(10.0, e));
      cv::line(img, cv::Point(left, y), cv::Point(w - right, y),
               cv::Scalar(215, 215, 215));
      std::ostringstream t;
      t << std::pow(10.0, e);
      cv::putText(img, t.str(), cv::Point(8, y + 4), cv::FONT_HERSHEY_SIMPLEX,
                  0.4, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::rectangle(img, cv::Point(left, y_top), cv::Point(w - right, y_bottom),
                  cv::Scalar(0, 0, 0));
    cv::putText(img, panel.label, cv::Point(left + 5, y_top - 6),
                cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                cv::LINE_AA);
    for (size_t i = 0; i < n; ++i) {
      const double v = errors[i].*panel.value;
      const int x = x_of(i);
      if (std::isnan(v)) {
        const bool expected =
            !panel.pen || (i < pen_in_truth.size() && pen_in_truth[i]);
        if (expected)
          cv::line(img, cv::Point(x, y_bottom + 2), cv::Point(x, y_bottom + 8),
                   cv::Scalar(0, 0, 220));
        continue;
      }
      cv::circle(
          img, cv::Point(x, y_of(v)), 2,
          errors[i].flip ? cv::Scalar(0, 0, 220) : cv::Scalar(160, 80, 0),
          cv::FILLED, cv::LINE_AA);
    }
    // Frame numbers under the panel: first, middle, last.
    for (size_t i : {size_t(0), n / 2, n ? n - 1 : 0}) {
      if (i >= frames.size()) continue;
      cv::putText(img, std::to_string(frames[i]),
                  cv::Point(x_of(i) - 10, y_bottom + 22),
                  cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1,
                  cv::LINE_AA);
    }
  }
  cv::putText(img,
              "frame; shaded: static segments of the truth; red dot: flip; "
              "red tick: no estimate",
              cv::Point(left, h - 12), cv::FONT_HERSHEY_SIMPLEX, 0.45,
              cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  return cv::imwrite(path, img);
}

}  // namespace ripple::bench

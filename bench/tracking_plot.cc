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
    const double x = median(s->ms), y = median(s->tip_mm);
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
    const double x = median(s.ms), y = median(s.tip_mm);
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

#include "bench/stage_table.h"

#include <cstdio>

#include "bench/stats.h"

namespace ripple::bench {
namespace {

struct Column {
  const char* name;
  double StageTimes::*field;
};
const Column kColumns[] = {
    {"cap", &StageTimes::cap},           {"det", &StageTimes::det},
    {"pose", &StageTimes::pose},         {"occ", &StageTimes::occ},
    {"drw", &StageTimes::drw},           {"sim", &StageTimes::sim},
    {"caustics", &StageTimes::caustics}, {"shadow", &StageTimes::shadow},
    {"total", &StageTimes::total},       {"lat", &StageTimes::lat}};

}  // namespace

StageTimes StageTable::RecentMedian(size_t last) const {
  const size_t first = rows_.size() > last ? rows_.size() - last : 0;
  StageTimes median;
  for (const Column& c : kColumns) {
    std::vector<double> v;
    for (size_t i = first; i < rows_.size(); ++i)
      v.push_back(rows_[i].*(c.field));
    median.*(c.field) = Percentile(v, 50);
  }
  return median;
}

std::string StageTable::Format(const std::string& label) const {
  std::string out;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s (%zu frames, ms)\n", label.c_str(),
                rows_.size());
  out += buf;
  std::snprintf(buf, sizeof(buf), "%-7s", "");
  out += buf;
  for (const Column& c : kColumns) {
    std::snprintf(buf, sizeof(buf), "%9s", c.name);
    out += buf;
  }
  out += "\n";
  for (double p : {50.0, 95.0}) {
    std::snprintf(buf, sizeof(buf), "%-7s", p == 50.0 ? "median" : "p95");
    out += buf;
    for (const Column& c : kColumns) {
      std::vector<double> v;
      for (const StageTimes& r : rows_) v.push_back(r.*(c.field));
      std::snprintf(buf, sizeof(buf), "%9.2f", Percentile(v, p));
      out += buf;
    }
    out += "\n";
  }
  return out;
}

bool StageTable::AppendCsv(const std::string& path, const std::string& label,
                           bool header, std::string* error) const {
  std::FILE* f = std::fopen(path.c_str(), header ? "w" : "a");
  if (!f) {
    if (error) *error = "cannot write timing file '" + path + "'";
    return false;
  }
  if (header) {
    std::fprintf(f, "label,stat");
    for (const Column& c : kColumns) std::fprintf(f, ",%s", c.name);
    std::fprintf(f, ",frames\n");
  }
  for (double p : {50.0, 95.0}) {
    std::fprintf(f, "%s,%s", label.c_str(), p == 50.0 ? "median" : "p95");
    for (const Column& c : kColumns) {
      std::vector<double> v;
      for (const StageTimes& r : rows_) v.push_back(r.*(c.field));
      std::fprintf(f, ",%.3f", Percentile(v, p));
    }
    std::fprintf(f, ",%zu\n", rows_.size());
  }
  const bool ok = std::fclose(f) == 0;
  if (!ok && error) *error = "cannot write timing file '" + path + "'";
  return ok;
}

}  // namespace ripple::bench

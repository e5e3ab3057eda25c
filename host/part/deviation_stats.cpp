#include <shapespline/part/deviation_stats.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>

namespace shapespline::part {

namespace {

// A distance's bin: the sign, exponent and first 10 mantissa bits of the (non-negative) double.
constexpr int kDroppedBits = 42;

std::uint32_t binOf(double d) { return static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(d) >> kDroppedBits); }
double upperEdge(std::uint32_t bin) { return std::bit_cast<double>(static_cast<std::uint64_t>(bin + 1) << kDroppedBits); }

}  // namespace

void DeviationStats::Tally::add(double d) {
  if (count == 0) min = max = d;
  min = std::min(min, d);
  max = std::max(max, d);
  ++count;
  sum += d;
  sumSquares += d * d;
  ++bins[binOf(d)];
}

void DeviationStats::add(int face, double distance) {
  all_.add(distance);
  faces_[face].add(distance);
}

const std::vector<double>& DeviationStats::percentileLevels() {
  static const std::vector<double> levels = {50.0, 90.0, 95.0, 99.0, 99.9};
  return levels;
}

DeviationStats::Summary DeviationStats::summarise(const Tally& t) {
  Summary s;
  s.count = t.count;
  if (t.count == 0) return s;
  s.min = t.min;
  s.max = t.max;
  s.mean = t.sum / static_cast<double>(t.count);
  s.rms = std::sqrt(t.sumSquares / static_cast<double>(t.count));
  std::vector<std::pair<std::uint32_t, std::uint64_t>> bins(t.bins.begin(), t.bins.end());
  std::sort(bins.begin(), bins.end());
  size_t at = 0;
  std::uint64_t below = 0;
  for (const double level : percentileLevels()) {
    // The smallest bin by which at least level% of the points have come.
    const auto needed = static_cast<std::uint64_t>(std::ceil(level / 100.0 * static_cast<double>(t.count)));
    while (at < bins.size() && below + bins[at].second < needed) below += bins[at++].second;
    const double edge = at < bins.size() ? upperEdge(bins[at].first) : t.max;
    s.percentiles.push_back(std::clamp(edge, t.min, t.max));
  }
  return s;
}

std::map<int, DeviationStats::Summary> DeviationStats::perFace() const {
  std::map<int, Summary> out;
  for (const auto& [face, tally] : faces_) out[face] = summarise(tally);
  return out;
}

std::string DeviationStats::text(bool faceColumn) const {
  std::string out;
  char line[512];
  const auto row = [&](const std::string& name, const Summary& s) {
    std::snprintf(line, sizeof line, "%-8s %12llu %13.6g %13.6g %13.6g %13.6g", name.c_str(),
                  static_cast<unsigned long long>(s.count), s.min, s.max, s.mean, s.rms);
    out += line;
    for (const double p : s.percentiles) {
      std::snprintf(line, sizeof line, " %13.6g", p);
      out += line;
    }
    out += '\n';
  };
  std::snprintf(line, sizeof line, "%-8s %12s %13s %13s %13s %13s", faceColumn ? "face" : "", "points", "min", "max",
                "mean", "rms");
  out += line;
  for (const double level : percentileLevels()) {
    std::snprintf(line, sizeof line, " %13s", ("p" + std::string(level == 99.9 ? "99.9" : std::to_string(int(level)))).c_str());
    out += line;
  }
  out += '\n';
  row("all", overall());
  if (faceColumn)
    for (const auto& [face, s] : perFace()) row(std::to_string(face), s);
  return out;
}

}  // namespace shapespline::part

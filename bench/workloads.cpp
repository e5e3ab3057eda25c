#include "workloads.h"

#include <shapespline/vk/error.h>

#include <benchmark/benchmark.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace shapespline::bench {
namespace {

bool gChecksOk = true;

struct GpuState {
  std::shared_ptr<vk::Context> ctx;
  std::string reason;
};

GpuState& gpuState() {
  static GpuState state = [] {
    GpuState s;
    try {
      vk::ContextOptions options;
      options.preferFp64 = true;
      s.ctx = vk::Context::create(options);
    } catch (const vk::NoDeviceError& e) {
      s.reason = std::string("no Vulkan device: ") + e.what();
    }
    return s;
  }();
  return state;
}

}  // namespace

SurfaceModel gridSurfaceModel(const FamilySpec& family, int n, unsigned seed) {
  SurfaceModel m;
  m.family = family;
  m.orderV = family.order;
  m.rows = n, m.cols = n;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.25, 0.25), alpha(0.3, 1.0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double h = 2.0 * std::sin(0.3 * i) * std::cos(0.2 * j) + noise(rng);
      m.points.emplace_back(i + noise(rng), j + noise(rng), h);
      if (family.construction == Construction::AlphaEB) m.alpha.push_back(alpha(rng));
    }
  return m;
}

CurveModel closedCurveModel(const FamilySpec& family, int n, unsigned seed) {
  CurveModel m;
  m.family = family;
  m.closed = true;
  m.dimension = 3;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.2, 0.2), alpha(0.3, 1.0);
  const double radius = n / (2 * M_PI);  // neighbouring points about 1 apart
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    m.points.emplace_back(radius * std::cos(a) + noise(rng), radius * std::sin(a) + noise(rng), noise(rng));
    if (family.construction == Construction::AlphaEB) m.alpha.push_back(alpha(rng));
  }
  return m;
}

double boxDiagonal(const std::vector<glm::dvec3>& points) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
  return glm::length(hi - lo);
}

std::shared_ptr<vk::Context> gpuContext() { return gpuState().ctx; }
const std::string& gpuUnavailableReason() { return gpuState().reason; }

ChunkConsumer touchConsumer(double& sink) {
  return [&sink](const GridChunk& c) {
    const size_t last = c.pointCount() * 3 - 1;
    for (int f = 0; f < kFieldCount; ++f)
      if (c.planes[f]) sink += c.coord(Field(f), 0, 0) + c.coord(Field(f), last / 3, 2);
  };
}

ChunkConsumer Collected::consumer() {
  return [this](const GridChunk& c) {
    for (int f = 0; f < kFieldCount; ++f)
      if (c.planes[f])
        for (size_t i = 0; i < c.pointCount(); ++i)
          for (int k = 0; k < 3; ++k) planes[f].push_back(c.coord(Field(f), i, k));
  };
}

double maxDiff(const Collected& a, const Collected& b, FieldMask fields, size_t* worstPoint) {
  double d = 0.0;
  for (int f = 0; f < kFieldCount; ++f) {
    if (!(fields & fieldBit(Field(f)))) continue;
    const auto &x = a.planes[f], &y = b.planes[f];
    if (x.size() != y.size() || x.empty()) return HUGE_VAL;
    for (size_t i = 0; i < x.size(); ++i) {
      const double e = std::abs(x[i] - y[i]);
      if (!(e <= d)) {
        d = e;
        if (worstPoint) *worstPoint = i / 3;
      }
    }
  }
  return d;
}

void reportCheck(const std::string& what, double maxDiff, double tolerance) {
  const bool ok = maxDiff <= tolerance;  // NaN fails
  gChecksOk = gChecksOk && ok;
  char text[160];
  std::snprintf(text, sizeof text, "max |diff| = %.3g (tolerance %.3g) %s", maxDiff, tolerance, ok ? "ok" : "FAILED");
  std::fprintf(stderr, "check: %s: %s\n", what.c_str(), text);
  benchmark::AddCustomContext("check: " + what, text);
}

void reportSkip(const std::string& what, const std::string& reason) {
  std::fprintf(stderr, "check: %s: skipped (%s)\n", what.c_str(), reason.c_str());
  benchmark::AddCustomContext("check: " + what, "skipped: " + reason);
}

bool allChecksPassed() { return gChecksOk; }

}  // namespace shapespline::bench

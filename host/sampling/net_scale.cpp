#include <shapespline/sampling/net_scale.h>

#include <shapespline/core/cores.h>
#include <shapespline/core/value_scan.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <thread>
#include <utility>

namespace shapespline::sampling {
namespace {

glm::dvec3 ldexp3(const glm::dvec3& p, int k) { return {std::ldexp(p.x, k), std::ldexp(p.y, k), std::ldexp(p.z, k)}; }

std::vector<glm::dvec3> scaled(std::vector<glm::dvec3> points, int k) {
  for (auto& p : points) p = ldexp3(p, k);
  return points;
}

}  // namespace

int netScaleFor(double m, Precision precision) {
  if (!(m > 0.0) || !std::isfinite(m)) return 0;
  const int e = std::ilogb(m);  // m in [2^e, 2^(e+1)), also for subnormal m (e down to -1074)
  const int band = precision == Precision::Float ? 20 : 200;
  return e >= -band && e < band ? 0 : -e;
}

int cpuNetScaleFor(double m) { return std::min(0, netScaleFor(m, Precision::Double)); }

double largestCoordinate(const std::vector<glm::dvec3>& points) {
  return largestMagnitude(reinterpret_cast<const double*>(points.data()), 3 * points.size());
}
double largestCoordinate(const Curve& curve) { return largestCoordinate(curve.model().points); }
double largestCoordinate(const Surface& surface) {
  double m = 0.0;
  surface.forEachControlRow([&m](const glm::dvec3* row, int cols) {
    m = std::max(m, largestMagnitude(reinterpret_cast<const double*>(row), 3 * static_cast<size_t>(cols)));
  });
  return m;
}

int netScale(const std::vector<glm::dvec3>& points, Precision precision) {
  return netScaleFor(largestCoordinate(points), precision);
}
int netScale(const Curve& curve, Precision precision) { return netScaleFor(largestCoordinate(curve), precision); }
int netScale(const Surface& surface, Precision precision) { return netScaleFor(largestCoordinate(surface), precision); }

Curve scaledCurve(const Curve& curve, int k) {
  CurveModel m = curve.model();
  m.points = scaled(std::move(m.points), k);
  return Curve::create(std::move(m));
}

Surface scaledSurface(const Surface& surface, int k) {
  SurfaceModel m = surface.toModel();
  m.points = scaled(std::move(m.points), k);
  return Surface::create(std::move(m));
}

void unscale(std::vector<CurvePoint>& points, int k) {
  if (k == 0) return;
  for (auto& p : points) p.point = ldexp3(p.point, -k), p.d1 = ldexp3(p.d1, -k), p.d2 = ldexp3(p.d2, -k);
}

void unscale(std::vector<SurfacePoint>& points, int k) {
  if (k == 0) return;
  for (auto& p : points) {
    p.point = ldexp3(p.point, -k), p.du = ldexp3(p.du, -k), p.dv = ldexp3(p.dv, -k);
    p.duu = ldexp3(p.duu, -k), p.duv = ldexp3(p.duv, -k), p.dvv = ldexp3(p.dvv, -k);
  }
}

void unscale(std::vector<CurveFirst>& points, int k) {
  if (k == 0) return;
  for (auto& p : points) p.point = ldexp3(p.point, -k), p.d1 = ldexp3(p.d1, -k);
}

void unscale(std::vector<SurfaceFirst>& points, int k) {
  if (k == 0) return;
  for (auto& p : points) p.point = ldexp3(p.point, -k), p.du = ldexp3(p.du, -k), p.dv = ldexp3(p.dv, -k);
}

void ChunkUnscaler::operator()(const GridChunk& chunk, const ChunkConsumer& consumer) {
  if (k_ == 0) return consumer(chunk);
  GridChunk out = chunk;
  const size_t n = chunk.pointCount() * 3;
  for (int f = 0; f < kFieldCount; ++f) {
    const void* src = chunk.planes[static_cast<size_t>(f)];
    if (!src || f == static_cast<int>(Field::Normal)) continue;
    if (chunk.precision == Precision::Double) {
      auto& buf = doubles_[static_cast<size_t>(f)];
      buf.resize(n);
      for (size_t i = 0; i < n; ++i) buf[i] = std::ldexp(static_cast<const double*>(src)[i], k_);
      out.planes[static_cast<size_t>(f)] = buf.data();
    } else {
      auto& buf = floats_[static_cast<size_t>(f)];
      buf.resize(n);
      for (size_t i = 0; i < n; ++i) {
        buf[i] = static_cast<float>(std::ldexp(static_cast<double>(static_cast<const float*>(src)[i]), k_));
      }
      out.planes[static_cast<size_t>(f)] = buf.data();
    }
  }
  consumer(out);
}

namespace {

// The slice stage of a chunk (valid during this call): one slice per hardware thread, run at once
// (SliceConsumer work is order-free), so that the checks and the writer's conversion of a GPU
// chunk take 1/T of the time the next dispatch has to run in.
void sliceInParallel(const SliceConsumer& slice, const GridChunk& chunk) {
  const size_t n = chunk.pointCount();
  const size_t threads = std::min<size_t>(static_cast<size_t>(availableCores()), (n + 4095) / 4096);
  if (threads <= 1) {
    slice(chunk, 0, n);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> failures(threads);
  for (size_t t = 1; t < threads; ++t) {
    pool.emplace_back([&, t] {
      try {
        slice(chunk, n * t / threads, n * (t + 1) / threads - n * t / threads);
      } catch (...) {
        failures[t] = std::current_exception();
      }
    });
  }
  try {
    slice(chunk, 0, n / threads);
  } catch (...) {
    failures[0] = std::current_exception();
  }
  for (auto& t : pool) t.join();
  for (const auto& f : failures) {
    if (f) std::rethrow_exception(f);
  }
}

}  // namespace

ChunkConsumer unscaledDelivery(ChunkUnscaler& unscale, const SliceConsumer& slice, const ChunkConsumer& consumer) {
  return [&unscale, &slice, &consumer](const GridChunk& chunk) {
    unscale(chunk, [&](const GridChunk& c) {
      if (slice) sliceInParallel(slice, c);
      consumer(c);
    });
  };
}

}  // namespace shapespline::sampling

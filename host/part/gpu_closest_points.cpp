#include <shapespline/part/gpu_closest_points.h>

#include <shapespline/core/parallel_for.h>
#include <shapespline/gpu/closest_point_search.h>
#include <shapespline/part/projection_tables.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace shapespline::part {

namespace pl = gpu::projection_layout;

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

GpuClosestPoints::GpuClosestPoints(const ClosestPoints& cpu, std::shared_ptr<vk::Context> ctx, Precision precision,
                                   gpu::EvaluatorOptions options)
    : cpu_(cpu) {
  FlatProjectionTree flat = flattenProjectionTree(cpu.tree(), cpu.tolerance(), precision);
  origin_ = flat.origin;
  faceCorners_ = std::move(flat.faceCorners);
  search_ = std::make_unique<gpu::ClosestPointSearch>(std::move(ctx), precision, flat.tables, options);
}

GpuClosestPoints::~GpuClosestPoints() = default;

void GpuClosestPoints::of(std::span<const glm::dvec3> points, std::span<FootPoint> out, bool signedDistance,
                          int threads) {
  redone_ = 0;
  if (cpu_.tree().nodes().empty()) {
    std::fill(out.begin(), out.end(), FootPoint{});
    return;
  }
  constexpr size_t kBlock = gpu::ClosestPointSearch::kQueriesPerDispatch;
  std::atomic<size_t> redone{0};
  std::vector<glm::dvec3> queries;
  std::vector<gpu::ProjectionHit> hits;
  for (size_t first = 0; first < points.size(); first += kBlock) {
    const size_t n = std::min(kBlock, points.size() - first);
    queries.resize(n);
    for (size_t k = 0; k < n; ++k) queries[k] = points[first + k] - origin_;
    hits.resize(n);
    search_->search(queries, hits);
    constexpr size_t kFinishBlock = 256;
    parallelFor((n + kFinishBlock - 1) / kFinishBlock, threads, [&](size_t b) {
      for (size_t k = b * kFinishBlock; k < std::min(n, (b + 1) * kFinishBlock); ++k) {
        const glm::dvec3& q = points[first + k];
        const gpu::ProjectionHit& h = hits[k];
        if (h.flags & pl::kHitRedo) {
          out[first + k] = cpu_.of(q, signedDistance);
          ++redone;
          continue;
        }
        ClosestPoints::Candidate c;
        if (h.flags & pl::kHitFound) {
          c.point = h.point + origin_;
          c.d2 = glm::dot(c.point - q, c.point - q);
          c.face = static_cast<int>(h.face);
          // Within the domain and the patch, which fp32's rounding of the offsets may leave.
          const Surface& s = *cpu_.tree().faces()[h.face].surface;
          const auto [u0, u1] = s.parameterRangeU();
          const auto [v0, v1] = s.parameterRangeV();
          c.u = std::clamp(h.uv.x + faceCorners_[h.face].x, u0, u1);
          c.v = std::clamp(h.uv.y + faceCorners_[h.face].y, v0, v1);
          c.boundary = (h.flags & pl::kHitBoundary) != 0;
          c.i = static_cast<int>(h.i), c.j = static_cast<int>(h.j);
          c.lu = std::clamp(h.local.x, 0.0, 1.0), c.lv = std::clamp(h.local.y, 0.0, 1.0);
          c.du = h.du, c.dv = h.dv;
          // A value fp32 could not hold (a part far beyond its range): the CPU's search instead.
          if (!finite(c.point) || !finite(c.du) || !finite(c.dv) || !finite({c.u, c.v, c.lu + c.lv})) {
            out[first + k] = cpu_.of(q, signedDistance);
            ++redone;
            continue;
          }
        }
        out[first + k] = cpu_.finish(q, c, signedDistance);
      }
    });
  }
  redone_ = redone;
}

}  // namespace shapespline::part

// shapespline_realtime_bench: the real-time adaptive frame (issue 18), every figure from one run.
//
// Workload: the 1,000-patch α-EB surface (bench::thousandPatchAlphaEB) at WIDTHxHEIGHT, a camera
// orbiting it (full circle in FRAMES frames, elevation 30°, closer than the framing distance so
// that near patches are large and far ones small), tolerance TOL pixels.
//  1. need: gpu::AdaptiveTessellator with no hysteresis; per frame its triangle count, and the
//     uniform rate of equal error R_u = the largest rate any patch needed (every patch meets the
//     tolerance at R_u; the uniform mesh has 2 R_u² triangles a patch);
//  2. adaptive frame: rate selection + tessellation (record + submit + wait, no draw), and the same
//     with the draw at WIDTHxHEIGHT (render::OffscreenRenderer, vkCmdDrawIndexedIndirect);
//  3. peers at the median R_u: our fixed-rate SurfaceTessellator re-tessellating, and OpenSubdiv's
//     Bfr (Bfr::Surface + Bfr::Tessellation, on THREADS threads) re-evaluating the same 1,000
//     patches as regular bicubic faces (points, partials and normals: what a renderer needs);
//  4. smoothness: rate changes per frame and the screen-space "pop" of the mesh they cause, with
//     and without hysteresis (docs/tessellation.md).
// Prints a table and writes JSON (--json PATH).
#include <shapespline/core/surface.h>
#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/adaptive_tessellator.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/render/renderer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/submit.h>
#include <shapespline/vk/timestamps.h>

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "../workloads.h"

namespace {

using namespace shapespline;
using Clock = std::chrono::steady_clock;
using gpu::tess_layout::TessVertex;

struct Args {
  int frames = 120, width = 1280, height = 720, maxRate = 64, threads = 2, reps = 5;
  float tol = 1.0f, hysteresis = 0.25f;
  std::string json;
};

double seconds(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// ---- the orbit ------------------------------------------------------------------------------------

struct Orbit {
  std::vector<render::Camera> cameras;
};

Orbit makeOrbit(const SurfaceModel& m, const Args& a) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : m.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * glm::length(hi - lo), aspect = double(a.width) / a.height;
  const double dist = 0.9 * radius;  // inside the framing distance: the near rim is large
  Orbit o;
  for (int f = 0; f < a.frames; ++f) {
    const double az = 2 * M_PI * f / a.frames, el = glm::radians(30.0);
    const glm::dvec3 eye = centre + dist * glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    o.cameras.push_back(render::Camera::look(eye, centre, glm::dvec3(0, 0, 1), 45.0, aspect, 0.02 * radius, 4.0 * radius));
  }
  return o;
}

gpu::AdaptiveView viewOf(const render::Camera& c, const Args& a) {
  gpu::AdaptiveView v;
  const glm::mat4 vp = c.viewProj();
  std::memcpy(v.viewProj.data(), &vp[0][0], sizeof(float) * 16);
  v.viewportWidth = float(a.width);
  v.viewportHeight = float(a.height);
  return v;
}

int largestRate(const TessRates& r) {
  int worst = 0;
  for (size_t p = 0; p < r.rateU.size(); ++p) worst = std::max({worst, r.rateU[p], r.rateV[p]});
  return worst;
}

// ---- OpenSubdiv Bfr --------------------------------------------------------------------------------

namespace osd = OpenSubdiv::OPENSUBDIV_VERSION;

// The same 25 x 40 patches as regular bicubic B-spline faces: a (rows + 2) x (cols + 2) vertex grid
// of quads (the net, extended linearly by one ring) whose faces away from the border are regular.
class BfrPeer {
 public:
  BfrPeer(const SurfaceModel& m) {
    const int R = m.rows + 2, C = m.cols + 2;
    auto at = [&](int i, int j) { return m.points[size_t(i) * m.cols + j]; };
    for (int i = 0; i < R; ++i)
      for (int j = 0; j < C; ++j) {
        // Net point (i - 1, j - 1); the ring outside the net continues it linearly.
        const int ci = std::clamp(i - 1, 0, m.rows - 1), cj = std::clamp(j - 1, 0, m.cols - 1);
        const int di = i - 1 - ci, dj = j - 1 - cj;
        const glm::dvec3 p = at(ci, cj) + double(di) * (at(ci, cj) - at(ci - di, cj)) +
                             double(dj) * (at(ci, cj) - at(ci, cj - dj));
        points_.insert(points_.end(), {float(p.x), float(p.y), float(p.z)});
      }
    std::vector<int> counts, verts;
    for (int i = 0; i + 1 < R; ++i)
      for (int j = 0; j + 1 < C; ++j) {
        counts.push_back(4);
        verts.insert(verts.end(), {i * C + j, (i + 1) * C + j, (i + 1) * C + j + 1, i * C + j + 1});
        // Faces whose 1-ring lies inside the grid are regular: the model's patches.
        if (i >= 1 && i + 2 < R && j >= 1 && j + 2 < C) faces_.push_back(int(counts.size()) - 1);
      }
    osd::Far::TopologyDescriptor desc;
    desc.numVertices = R * C;
    desc.numFaces = int(counts.size());
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = verts.data();
    osd::Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(osd::Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    refiner_.reset(osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>::Create(
        desc, osd::Far::TopologyRefinerFactory<osd::Far::TopologyDescriptor>::Options(osd::Sdc::SCHEME_CATMARK, sdc)));
    factory_ = std::make_unique<osd::Bfr::RefinerSurfaceFactory<>>(*refiner_);
    surfaces_.resize(faces_.size());
    for (size_t f = 0; f < faces_.size(); ++f) {
      factory_->InitVertexSurface(faces_[f], &surfaces_[f]);
      regular_ += surfaces_[f].IsRegular() ? 1 : 0;
    }
  }

  size_t faces() const { return faces_.size(); }
  size_t regular() const { return regular_; }

  void setRate(int rate) {
    tess_ = std::make_unique<osd::Bfr::Tessellation>(surfaces_.front().GetParameterization(),
                                                     rate, osd::Bfr::Tessellation::Options());
    coords_.resize(size_t(tess_->GetNumCoords()) * 2);
    tess_->GetCoords(coords_.data());
    out_.resize(faces_.size() * tess_->GetNumCoords() * 6);
  }
  size_t vertices() const { return faces_.size() * size_t(tess_->GetNumCoords()); }
  size_t triangles() const { return faces_.size() * size_t(tess_->GetNumFacets()); }

  // Re-evaluates every face (patch points from the mesh, then point + partials -> position and
  // normal) on `threads` threads.
  void evaluate(int threads) {
    auto work = [&](size_t f0, size_t f1) {
      std::vector<float> patch;
      const osd::Bfr::Surface<float>::PointDescriptor d(3);
      const int nc = tess_->GetNumCoords();
      for (size_t f = f0; f < f1; ++f) {
        const auto& s = surfaces_[f];
        patch.resize(size_t(s.GetNumPatchPoints()) * 3);
        s.PreparePatchPoints(points_.data(), d, patch.data(), d);
        float* o = out_.data() + f * nc * 6;
        for (int k = 0; k < nc; ++k, o += 6) {
          float du[3], dv[3];
          s.Evaluate(&coords_[2 * k], patch.data(), d, o, du, dv);
          const glm::vec3 n = glm::normalize(glm::cross(glm::vec3(du[0], du[1], du[2]), glm::vec3(dv[0], dv[1], dv[2])));
          o[3] = n.x;
          o[4] = n.y;
          o[5] = n.z;
        }
      }
    };
    std::vector<std::thread> pool;
    const size_t n = faces_.size();
    for (int t = 0; t < threads; ++t) pool.emplace_back(work, n * t / threads, n * (t + 1) / threads);
    for (auto& th : pool) th.join();
  }

 private:
  std::vector<float> points_;
  std::vector<int> faces_;
  size_t regular_ = 0;
  std::unique_ptr<osd::Far::TopologyRefiner> refiner_;
  std::unique_ptr<osd::Bfr::RefinerSurfaceFactory<>> factory_;
  std::vector<osd::Bfr::Surface<float>> surfaces_;
  std::unique_ptr<osd::Bfr::Tessellation> tess_;
  std::vector<float> coords_, out_;
};

// ---- smoothness: the mesh's position at a parameter ---------------------------------------------

// The point of a frame's mesh at local (u, v) of patch p: barycentric in the triangle of the
// topology that contains (u, v) in parameter space.
class MeshAt {
 public:
  MeshAt(const gpu::AdaptiveTessellator::Mesh& mesh) : mesh_(mesh), topo_(buildTessTopology(mesh.rates)) {}

  glm::dvec3 operator()(int a, int b, double u, double v) const {
    const TessRates& r = topo_.rates;
    const size_t p = size_t(a) * r.patchesV + b;
    const uint32_t first = topo_.firstIndex[p], end = first + topo_.indexCount[p];
    for (uint32_t t = first; t < end; t += 3) {
      glm::dvec2 q[3];
      for (int c = 0; c < 3; ++c) q[c] = local(topo_.indices[t + c], a, b);
      const double det = (q[1].x - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (q[1].y - q[0].y);
      const double l1 = ((u - q[0].x) * (q[2].y - q[0].y) - (q[2].x - q[0].x) * (v - q[0].y)) / det;
      const double l2 = ((q[1].x - q[0].x) * (v - q[0].y) - (u - q[0].x) * (q[1].y - q[0].y)) / det;
      const double l0 = 1.0 - l1 - l2, eps = -1e-9;
      if (l0 < eps || l1 < eps || l2 < eps) continue;
      return l0 * position(topo_.indices[t]) + l1 * position(topo_.indices[t + 1]) + l2 * position(topo_.indices[t + 2]);
    }
    return position(topo_.indices[first]);  // not reached for (u, v) in [0,1]^2
  }

 private:
  glm::dvec2 local(uint32_t k, int a, int b) const {
    const TessSample& s = topo_.samples[k];
    return {s.a - a + s.u, s.b - b + s.v};
  }
  glm::dvec3 position(uint32_t k) const {
    const TessVertex& x = mesh_.vertices[k];
    return {x.position[0], x.position[1], x.position[2]};
  }
  const gpu::AdaptiveTessellator::Mesh& mesh_;
  TessTopology topo_;
};

struct Smoothness {
  double framesWithChanges = 0, patchesChangedPerFrame = 0, popMeanPx = 0, popMaxPx = 0;
};

// Orbits with `hysteresis`; between frames k and k+1, the mesh of frame k and of frame k+1 are
// compared under camera k+1 at a 9 x 9 parameter grid of every patch whose rates changed, where
// the point was on screen in both frames.
Smoothness measureSmoothness(vk::Context& ctx, gpu::AdaptiveTessellator& tess, const Orbit& orbit, const Args& a) {
  tess.resetRates();
  Smoothness s;
  std::unique_ptr<gpu::AdaptiveTessellator::Mesh> prev;
  double popSum = 0;
  size_t popSamples = 0;
  int changedFrames = 0;
  size_t changedPatches = 0;
  for (size_t f = 0; f < orbit.cameras.size(); ++f) {
    vk::runOneShot(ctx, [&](VkCommandBuffer cmd) { tess.record(cmd, viewOf(orbit.cameras[f], a)); });
    auto mesh = std::make_unique<gpu::AdaptiveTessellator::Mesh>(tess.mesh());
    if (prev) {
      const TessRates &r0 = prev->rates, &r1 = mesh->rates;
      const MeshAt before(*prev), after(*mesh);
      const glm::dmat4 vp(orbit.cameras[f].viewProj()), vpBefore(orbit.cameras[f - 1].viewProj());
      auto pixel = [&](const glm::dvec3& p) {
        const glm::dvec4 c = vp * glm::dvec4(p, 1.0);
        return glm::dvec2(c.x / c.w * 0.5 * a.width, c.y / c.w * 0.5 * a.height);
      };
      int changed = 0;
      for (int pa = 0; pa < r1.patchesU; ++pa)
        for (int pb = 0; pb < r1.patchesV; ++pb) {
          const size_t p = size_t(pa) * r1.patchesV + pb;
          // A patch's mesh depends on its rates and its neighbours' (edge rates).
          bool moved = false;
          for (int da = -1; da <= 1 && !moved; ++da)
            for (int db = -1; db <= 1 && !moved; ++db) {
              const int qa = pa + da, qb = pb + db;
              if (qa < 0 || qb < 0 || qa >= r1.patchesU || qb >= r1.patchesV) continue;
              const size_t q = size_t(qa) * r1.patchesV + qb;
              moved = r0.rateU[q] != r1.rateU[q] || r0.rateV[q] != r1.rateV[q];
            }
          if (!moved) continue;
          ++changed;
          // Clamped or near-plane patches (rate maxRate) are outside the bound: not measured.
          const int top = std::max({r0.rateU[p], r0.rateV[p], r1.rateU[p], r1.rateV[p]});
          if (top >= a.maxRate) continue;
          for (int i = 0; i <= 8; ++i)
            for (int j = 0; j <= 8; ++j) {
              // Seen in both frames: on screen before (camera k) and after (camera k+1).
              const glm::dvec4 c = vp * glm::dvec4(after(pa, pb, i / 8.0, j / 8.0), 1.0);
              const glm::dvec4 c0 = vpBefore * glm::dvec4(before(pa, pb, i / 8.0, j / 8.0), 1.0);
              if (c.w <= 0 || std::abs(c.x) > c.w || std::abs(c.y) > c.w) continue;
              if (c0.w <= 0 || std::abs(c0.x) > c0.w || std::abs(c0.y) > c0.w) continue;
              const double d = glm::length(pixel(after(pa, pb, i / 8.0, j / 8.0)) - pixel(before(pa, pb, i / 8.0, j / 8.0)));
              popSum += d;
              ++popSamples;
              s.popMaxPx = std::max(s.popMaxPx, d);
            }
        }
      changedFrames += changed > 0;
      changedPatches += size_t(changed);
    }
    prev = std::move(mesh);
  }
  const double transitions = double(orbit.cameras.size() - 1);
  s.framesWithChanges = changedFrames / transitions;
  s.patchesChangedPerFrame = double(changedPatches) / transitions;
  s.popMeanPx = popSamples ? popSum / double(popSamples) : 0.0;
  return s;
}

int parseArgs(int argc, char** argv, Args& a) {
  for (int k = 1; k < argc; ++k) {
    const std::string s = argv[k];
    auto value = [&](const char* name) -> std::string {
      if (k + 1 >= argc) throw std::invalid_argument(std::string(name) + " needs a value");
      return argv[++k];
    };
    if (s == "--frames") a.frames = std::stoi(value("--frames"));
    else if (s == "--tolerance") a.tol = std::stof(value("--tolerance"));
    else if (s == "--max-rate") a.maxRate = std::stoi(value("--max-rate"));
    else if (s == "--threads") a.threads = std::stoi(value("--threads"));
    else if (s == "--reps") a.reps = std::stoi(value("--reps"));
    else if (s == "--json") a.json = value("--json");
    else if (s == "--help") {
      std::printf("usage: shapespline_realtime_bench [--frames N] [--tolerance PX] [--max-rate R] [--threads T] [--reps N] [--json PATH]\n");
      return 1;
    } else
      throw std::invalid_argument("unknown option " + s);
  }
  if (a.frames < 4 || a.tol <= 0 || a.threads < 1 || a.reps < 1) throw std::invalid_argument("bad option value");
  return 0;
}

}  // namespace

int main(int argc, char** argv) try {
  Args a;
  if (parseArgs(argc, argv, a)) return 0;
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::create();
  } catch (const vk::NoDeviceError& e) {
    std::fprintf(stderr, "realtime bench: no Vulkan device: %s\n", e.reason().c_str());
    return 2;
  }
  const SurfaceModel model = bench::thousandPatchAlphaEB();
  const Surface cpu = Surface::create(model);
  gpu::GpuSurface surface(ctx, cpu, Precision::Float);
  const Orbit orbit = makeOrbit(model, a);
  const size_t patches = surface.patchCount();

  // 1. What the tolerance needs, frame by frame (no hysteresis).
  gpu::AdaptiveOptions needOpt;
  needOpt.tolerancePx = a.tol;
  needOpt.maxRate = a.maxRate;
  needOpt.hysteresis = 0.0f;
  gpu::AdaptiveTessellator need(ctx, surface, needOpt);
  std::vector<double> adaptiveTris, uniformTris, uniformRates;
  uint32_t clampedFrames = 0, culled = 0;
  for (const auto& cam : orbit.cameras) {
    vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { need.record(cmd, viewOf(cam, a)); });
    const gpu::AdaptiveStats st = need.stats();
    const int ru = largestRate(need.rates());
    adaptiveTris.push_back(st.indexCount / 3.0);
    uniformTris.push_back(2.0 * ru * ru * double(patches));
    uniformRates.push_back(ru);
    clampedFrames += (st.clampedPatches + st.nearPatches) > 0;
    culled += st.culledPatches;
  }
  std::vector<double> triRatio;
  for (size_t f = 0; f < adaptiveTris.size(); ++f) triRatio.push_back(uniformTris[f] / adaptiveTris[f]);
  const int uniformRate = int(median(uniformRates));

  // 2. The adaptive frame: rate selection + tessellation, then with the draw.
  gpu::AdaptiveOptions opt = needOpt;
  opt.hysteresis = a.hysteresis;
  gpu::AdaptiveTessellator tess(ctx, surface, opt);
  render::OffscreenRenderer renderer(ctx, a.width, a.height);
  render::Scene scene;
  render::MeshDraw draw;
  draw.vertexBuffer = tess.vertexBuffer().handle();
  draw.indexBuffer = tess.indexBuffer().handle();
  draw.indirectBuffer = tess.indirectBuffer().handle();
  scene.meshes.push_back(draw);
  size_t frameIndex = 0;
  scene.prepare = [&](VkCommandBuffer cmd) { tess.record(cmd, viewOf(orbit.cameras[frameIndex], a)); };
  std::vector<double> tessMs, frameMs;
  vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { tess.record(cmd, viewOf(orbit.cameras[0], a)); });  // warm-up
  renderer.renderOnly(scene, orbit.cameras[0]);
  for (frameIndex = 0; frameIndex < orbit.cameras.size(); ++frameIndex) {
    const auto t0 = Clock::now();
    vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { tess.record(cmd, viewOf(orbit.cameras[frameIndex], a)); });
    const auto t1 = Clock::now();
    renderer.renderOnly(scene, orbit.cameras[frameIndex]);
    const auto t2 = Clock::now();
    tessMs.push_back(1e3 * seconds(t0, t1));
    frameMs.push_back(1e3 * seconds(t1, t2));
  }

  // 2b. Where the adaptive frame's time goes: GPU timestamps after each pass (the same orbit again).
  vk::PassTimer timer(*ctx, 16);
  std::vector<std::string> passNames;
  std::vector<std::vector<double>> passMs;
  std::vector<double> gpuTotalMs;
  for (const auto& cam : orbit.cameras) {
    vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { tess.record(cmd, viewOf(cam, a), &timer); });
    const auto passes = timer.passes();
    double total = 0;
    for (size_t k = 0; k < passes.size(); ++k) {
      if (passMs.size() <= k) {
        passNames.push_back(passes[k].first);
        passMs.emplace_back();
      }
      passMs[k].push_back(passes[k].second);
      total += passes[k].second;
    }
    if (!passes.empty()) gpuTotalMs.push_back(total);
  }

  // 3. Peers at the median uniform rate of equal error.
  gpu::SurfaceTessellator fixed(ctx, surface, gpu::SurfaceTessellator::uniformRates(surface, uniformRate));
  vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { fixed.record(cmd); });
  std::vector<double> fixedMs;
  for (int r = 0; r < a.reps; ++r) {
    const auto t0 = Clock::now();
    vk::runOneShot(*ctx, [&](VkCommandBuffer cmd) { fixed.record(cmd); });
    fixedMs.push_back(1e3 * seconds(t0, Clock::now()));
  }
  BfrPeer bfr(model);
  bfr.setRate(uniformRate);
  bfr.evaluate(a.threads);  // warm-up
  std::vector<double> bfrMs;
  for (int r = 0; r < a.reps; ++r) {
    const auto t0 = Clock::now();
    bfr.evaluate(a.threads);
    bfrMs.push_back(1e3 * seconds(t0, Clock::now()));
  }

  // 4. Smoothness with and without hysteresis.
  const Smoothness withH = measureSmoothness(*ctx, tess, orbit, a);
  const Smoothness without = measureSmoothness(*ctx, need, orbit, a);

  const double tessMed = median(tessMs), frameMed = median(frameMs), bfrMed = median(bfrMs);
  std::string passesJson;
  for (size_t k = 0; k < passNames.size(); ++k)
    passesJson += (k ? ", \"" : "\"") + passNames[k] + "\": " + std::to_string(median(passMs[k]));
  std::printf("realtime bench on %s: %zu patches, %dx%d, tolerance %.2f px, %d frames orbiting\n",
              ctx->deviceName().c_str(), patches, a.width, a.height, a.tol, a.frames);
  std::printf("  adaptive triangles per frame (median)      %10.0f\n", median(adaptiveTris));
  std::printf("  uniform rate of equal error (median, max)  %10d %d%s\n", uniformRate,
              int(*std::max_element(uniformRates.begin(), uniformRates.end())),
              clampedFrames ? "  (some frames clamped at max-rate: the uniform rate is a lower bound)" : "");
  std::printf("  uniform triangles / adaptive (median)      %10.2f  (target >= 3)\n", median(triRatio));
  std::printf("  adaptive: rates + tessellation, ms (med)   %10.2f\n", tessMed);
  std::printf("  adaptive: draw 1280x720, ms (median)       %10.2f\n", frameMed);
  if (!gpuTotalMs.empty()) {
    std::printf("  adaptive: GPU time of the passes, ms (med) %10.2f\n", median(gpuTotalMs));
    for (size_t k = 0; k < passNames.size(); ++k)
      std::printf("    %-38s %10.3f\n", passNames[k].c_str(), median(passMs[k]));
  }
  std::printf("  fixed-rate %d: re-tessellation, ms (med)   %10.2f  (%zu vertices)\n", uniformRate, median(fixedMs),
              size_t(fixed.vertexCount()));
  std::printf("  Bfr rate %d on %d threads, ms (median)     %10.2f  (%zu faces, %zu regular, %zu vertices)\n",
              uniformRate, a.threads, bfrMed, bfr.faces(), bfr.regular(), bfr.vertices());
  std::printf("  Bfr / adaptive frame                       %10.2f  (target >= 8)\n", bfrMed / tessMed);
  std::printf("  smoothness            hysteresis %.2f    none\n", a.hysteresis);
  std::printf("    frames with changes       %8.2f  %8.2f\n", withH.framesWithChanges, without.framesWithChanges);
  std::printf("    patches changed / frame   %8.2f  %8.2f\n", withH.patchesChangedPerFrame, without.patchesChangedPerFrame);
  std::printf("    pop mean px               %8.3f  %8.3f\n", withH.popMeanPx, without.popMeanPx);
  std::printf("    pop max px                %8.3f  %8.3f  (bound: 2 x tolerance)\n", withH.popMaxPx, without.popMaxPx);
  if (!a.json.empty()) {
    std::ofstream j(a.json);
    j << "{\n  \"device\": \"" << ctx->deviceName() << "\",\n  \"patches\": " << patches << ",\n  \"width\": " << a.width
      << ", \"height\": " << a.height << ", \"tolerance_px\": " << a.tol << ", \"frames\": " << a.frames
      << ",\n  \"adaptive_triangles_median\": " << median(adaptiveTris) << ",\n  \"uniform_rate_median\": " << uniformRate
      << ",\n  \"uniform_over_adaptive_triangles_median\": " << median(triRatio)
      << ",\n  \"adaptive_rates_and_tessellation_ms_median\": " << tessMed << ",\n  \"adaptive_draw_ms_median\": " << frameMed
      << ",\n  \"adaptive_gpu_ms_median\": " << median(gpuTotalMs) << ",\n  \"adaptive_gpu_passes_ms_median\": {" << passesJson
      << "}"
      << ",\n  \"fixed_rate_retessellation_ms_median\": " << median(fixedMs) << ",\n  \"bfr_ms_median\": " << bfrMed
      << ", \"bfr_threads\": " << a.threads << ",\n  \"bfr_over_adaptive\": " << bfrMed / tessMed
      << ",\n  \"smoothness\": {\"hysteresis\": " << a.hysteresis << ", \"frames_with_changes\": [" << withH.framesWithChanges
      << ", " << without.framesWithChanges << "], \"patches_changed_per_frame\": [" << withH.patchesChangedPerFrame << ", "
      << without.patchesChangedPerFrame << "], \"pop_mean_px\": [" << withH.popMeanPx << ", " << without.popMeanPx
      << "], \"pop_max_px\": [" << withH.popMaxPx << ", " << without.popMaxPx << "]},\n  \"culled_patch_frames\": " << culled
      << "\n}\n";
  }
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "realtime bench: %s\n", e.what());
  return 1;
}

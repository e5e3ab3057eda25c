// Re-tessellation after a λ change of a 1,000-patch α-EB surface at 32 x 32 segments per patch
// (about 1 M vertices), recorded with SurfaceTessellator::record and submitted on the default
// device, and the time to render that frame at 1280 x 720 (render/renderer.h, no readback).
// Reported per iteration: vertices, triangles; manual timing covers submit + wait.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <memory>

#include <shapespline/core/surface.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/render/renderer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/submit.h>

#include "workloads.h"

namespace {

using namespace shapespline;

struct Fixture {
  std::shared_ptr<vk::Context> ctx;
  std::unique_ptr<gpu::GpuSurface> surface;
  std::unique_ptr<gpu::SurfaceTessellator> tess;
  Fixture() {
    ctx = vk::Context::create();
    surface = std::make_unique<gpu::GpuSurface>(ctx, Surface::create(bench::thousandPatchAlphaEB()), Precision::Float);
    tess = std::make_unique<gpu::SurfaceTessellator>(ctx, *surface, gpu::SurfaceTessellator::uniformRates(*surface, 32));
  }
};

Fixture* fixture(benchmark::State& state) {
  static std::unique_ptr<Fixture> f;
  if (!f) {
    try {
      f = std::make_unique<Fixture>();
    } catch (const vk::NoDeviceError& e) {
      state.SkipWithError(("no Vulkan device: " + e.reason()).c_str());
      return nullptr;
    }
  }
  return f.get();
}

void BM_RetessellateAfterLambda(benchmark::State& state) {
  Fixture* f = fixture(state);
  if (!f) return;
  vk::runOneShot(*f->ctx, [&](VkCommandBuffer cmd) { f->tess->record(cmd); });  // warm-up: pipelines
  double lambda = 0.0;
  for (auto _ : state) {
    lambda = lambda == 0.0 ? -1.0 : 0.0;
    const auto t0 = std::chrono::steady_clock::now();
    f->surface->setLambda(lambda);
    vk::runOneShot(*f->ctx, [&](VkCommandBuffer cmd) { f->tess->record(cmd); });
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.counters["vertices"] = f->tess->vertexCount();
  state.counters["triangles"] = f->tess->indexCount() / 3.0;
  state.SetLabel(f->ctx->deviceName());
}
BENCHMARK(BM_RetessellateAfterLambda)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_RenderFrame1280x720(benchmark::State& state) {
  Fixture* f = fixture(state);
  if (!f) return;
  render::OffscreenRenderer renderer(f->ctx, 1280, 720);
  render::Scene scene;
  scene.meshes.push_back({f->tess->vertexBuffer().handle(), f->tess->indexBuffer().handle(), f->tess->indexCount()});
  const render::Camera cam = render::Camera::frame({0, 0, -0.5}, {25, 40, 0.5}, 35.0, 30.0, 1280.0 / 720.0);
  const bool withTess = state.range(0) != 0;
  if (withTess) scene.prepare = [&](VkCommandBuffer cmd) { f->tess->record(cmd); };
  renderer.renderOnly(scene, cam);  // warm-up
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    renderer.renderOnly(scene, cam);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  state.SetLabel(withTess ? "tessellate + draw" : "draw only");
}
BENCHMARK(BM_RenderFrame1280x720)->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

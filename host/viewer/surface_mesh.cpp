#include <shapespline/viewer/surface_mesh.h>

#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/adaptive_tessellator.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/vk/buffer.h>

#include <glm/gtc/type_ptr.hpp>

#include <cstring>
#include <span>
#include <stdexcept>

namespace shapespline::viewer {
namespace {

// The adaptive tessellator's default maximum rate, lowered until its worst-case mesh fits the
// device; below kMinAdaptiveRate the viewer falls back to a fixed-rate mesh.
constexpr int kMaxRate = 64, kMinAdaptiveRate = 8;
constexpr int kFixedRate = 16;

class AdaptiveMesh final : public SurfaceMesh {
 public:
  AdaptiveMesh(std::shared_ptr<vk::Context> ctx, gpu::GpuSurface& surface, gpu::AdaptiveOptions options,
               bool triangleWireframe)
      : tess_(std::move(ctx), surface, options), triangleWireframe_(triangleWireframe) {}

  std::string name() const override { return "adaptive, max rate " + std::to_string(tess_.options().maxRate); }

  void setTolerance(float px) override {
    if (px == tess_.options().tolerancePx) return;
    gpu::AdaptiveOptions o = tess_.options();
    o.tolerancePx = px;
    tess_.setOptions(o);  // same maxRate: no reallocation, no wait
  }

  void record(VkCommandBuffer cmd, const render::Camera& camera, VkExtent2D extent) override {
    gpu::AdaptiveView view;
    const glm::mat4 vp = camera.viewProj();
    std::memcpy(view.viewProj.data(), glm::value_ptr(vp), sizeof(float) * 16);
    view.viewportWidth = float(extent.width);
    view.viewportHeight = float(extent.height);
    tess_.record(cmd, view);
  }

  render::MeshDraw draw(bool wireframe) const override {
    render::MeshDraw m;
    m.vertexBuffer = tess_.vertexBuffer().handle();
    m.indexBuffer = tess_.indexBuffer().handle();
    m.indirectBuffer = tess_.indirectBuffer().handle();
    // The GPU-written triangles have no edge list: polygonMode LINE draws their edges (docs/viewer.md).
    m.wireframe = wireframe && triangleWireframe_;
    return m;
  }

  uint64_t triangleCount() const override { return tess_.stats().indexCount / 3; }

 private:
  gpu::AdaptiveTessellator tess_;
  bool triangleWireframe_;
};

class FixedRateMesh final : public SurfaceMesh {
 public:
  FixedRateMesh(const std::shared_ptr<vk::Context>& ctx, gpu::GpuSurface& surface, int rate)
      : tess_(ctx, surface, gpu::SurfaceTessellator::uniformRates(surface, rate)), rate_(rate) {
    const std::vector<uint32_t> edges = triangleEdges(tess_.topology().indices);
    wire_ = vk::Buffer::create(*ctx, edges.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               vk::MemoryUse::DeviceLocal, "viewer.wire");
    wire_.uploadSpan(std::span<const uint32_t>(edges));
    wireCount_ = uint32_t(edges.size());
  }

  std::string name() const override { return "fixed rate " + std::to_string(rate_); }
  void setTolerance(float) override {}
  void record(VkCommandBuffer cmd, const render::Camera&, VkExtent2D) override { tess_.record(cmd); }

  render::MeshDraw draw(bool wireframe) const override {
    render::MeshDraw m{tess_.vertexBuffer().handle(), tess_.indexBuffer().handle(), tess_.indexCount()};
    if (wireframe) {
      m.wireIndexBuffer = wire_.handle();
      m.wireIndexCount = wireCount_;
    }
    return m;
  }

  uint64_t triangleCount() const override { return tess_.indexCount() / 3; }

 private:
  gpu::SurfaceTessellator tess_;
  int rate_;
  vk::Buffer wire_;
  uint32_t wireCount_ = 0;
};

}  // namespace

std::unique_ptr<SurfaceMesh> makeSurfaceMesh(std::shared_ptr<vk::Context> ctx, gpu::GpuSurface& surface,
                                             float tolerancePx, bool triangleWireframe) {
  gpu::AdaptiveOptions options;
  options.tolerancePx = tolerancePx;
  for (options.maxRate = kMaxRate; options.maxRate >= kMinAdaptiveRate; options.maxRate /= 2) {
    try {
      return std::make_unique<AdaptiveMesh>(ctx, surface, options, triangleWireframe);
    } catch (const std::length_error&) {
      // The worst-case mesh at this maxRate exceeds the device's buffer range: try half.
    }
  }
  return std::make_unique<FixedRateMesh>(ctx, surface, kFixedRate);
}

}  // namespace shapespline::viewer

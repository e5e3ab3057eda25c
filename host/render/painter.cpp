#include <shapespline/render/painter.h>

#include <shapespline/core/tess_topology.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/error.h>

#include <span>

namespace shapespline::render {

struct SurfaceDrawing::Impl {
  Impl(const std::shared_ptr<vk::Context>& ctx, const Surface& surface, int rate)
      : model(ctx, surface, Precision::Float),
        tessellator(ctx, model, gpu::SurfaceTessellator::uniformRates(model, rate)) {}
  gpu::GpuSurface model;
  gpu::SurfaceTessellator tessellator;
  vk::Buffer wire;            // line-list indices of the triangle edges (wireframe only)
  uint32_t wireCount = 0;
};

Painter::Painter(int width, int height) {
  try {
    ctx_ = vk::Context::create();
  } catch (const vk::NoDeviceError& e) {
    throw NoRenderDeviceError("render needs a Vulkan device with a graphics queue: " + e.reason());
  }
  renderer_ = std::make_unique<OffscreenRenderer>(ctx_, width, height);
}

Painter::~Painter() = default;

std::unique_ptr<SurfaceDrawing> Painter::tessellate(const Surface& surface, int rate, bool wireframe) {
  auto impl = std::make_unique<SurfaceDrawing::Impl>(ctx_, surface, rate);
  if (wireframe) {
    const std::vector<uint32_t> edges = triangleEdges(impl->tessellator.topology().indices);
    impl->wire = vk::Buffer::create(*ctx_, edges.size() * 4,
                                    VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    vk::MemoryUse::DeviceLocal, "render.wire");
    impl->wire.uploadSpan(std::span<const uint32_t>(edges));
    impl->wireCount = static_cast<uint32_t>(edges.size());
  }
  return std::unique_ptr<SurfaceDrawing>(new SurfaceDrawing(std::move(impl)));
}

std::unique_ptr<StaticMesh> Painter::upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                                            std::span<const uint32_t> triangles, std::span<const uint32_t> lines) {
  return std::make_unique<StaticMesh>(*ctx_, positions, normals, triangles, lines);
}

Image Painter::draw(SurfaceDrawing& surface, const Scene& overlay, const Camera& camera) {
  Scene scene = overlay;
  scene.prepare = [&](VkCommandBuffer cmd) { surface.record(cmd); };
  scene.meshes.push_back(surface.mesh());
  return renderer_->render(scene, camera);
}

Image Painter::draw(const Scene& overlay, const Camera& camera) { return renderer_->render(overlay, camera); }

SurfaceDrawing::SurfaceDrawing(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SurfaceDrawing::~SurfaceDrawing() = default;

void SurfaceDrawing::setLambda(double lambda) { impl_->model.setLambda(lambda); }
void SurfaceDrawing::setAlphas(const std::vector<double>& alpha) { impl_->model.setAlphas(alpha); }

MeshDraw SurfaceDrawing::mesh() const {
  MeshDraw mesh;
  mesh.vertexBuffer = impl_->tessellator.vertexBuffer().handle();
  mesh.indexBuffer = impl_->tessellator.indexBuffer().handle();
  mesh.indexCount = impl_->tessellator.indexCount();
  if (impl_->wireCount > 0) {
    mesh.wireIndexBuffer = impl_->wire.handle();
    mesh.wireIndexCount = impl_->wireCount;
  }
  return mesh;
}

void SurfaceDrawing::record(VkCommandBuffer cmd) { impl_->tessellator.record(cmd); }

}  // namespace shapespline::render

#include <shapespline/render/renderer.h>

#include <shapespline/render/scene_pipelines.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/handle.h>
#include <shapespline/vk/submit.h>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include <stdexcept>
#include <string>

namespace shapespline::render {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

}  // namespace

struct OffscreenRenderer::Impl {
  Attachment color, depth;
  RenderPassHandle renderPass;
  FramebufferHandle framebuffer;
  std::unique_ptr<ScenePipelines> pipelines;
  vk::Buffer readback;
};

OffscreenRenderer::OffscreenRenderer(std::shared_ptr<vk::Context> ctx, int width, int height)
    : ctx_(std::move(ctx)), width_(width), height_(height), impl_(std::make_unique<Impl>()) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw std::invalid_argument("render size " + std::to_string(width) + " x " + std::to_string(height) +
                                " must lie in 1..16384 per side");
  vk::Context& c = *ctx_;
  VkDevice dev = c.device();
  {
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c.physicalDevice(), &n, nullptr);
    std::vector<VkQueueFamilyProperties> fam(n);
    vkGetPhysicalDeviceQueueFamilyProperties(c.physicalDevice(), &n, fam.data());
    if (c.queueFamily() >= n || !(fam[c.queueFamily()].queueFlags & VK_QUEUE_GRAPHICS_BIT))
      throw std::runtime_error("rendering needs a graphics queue; queue family " + std::to_string(c.queueFamily()) +
                               " of '" + c.deviceName() + "' has none");
  }
  const VkFormat df = depthAttachmentFormat(c);
  impl_->color = makeAttachment(c, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                VK_IMAGE_ASPECT_COLOR_BIT, width, height);
  impl_->depth = makeAttachment(c, df, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, width, height);

  // The colour ends in TRANSFER_SRC for the readback copy; the previous frame's copy finishes first.
  impl_->renderPass = makeColorDepthPass(c, kColorFormat, df, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                         VK_PIPELINE_STAGE_TRANSFER_BIT, "offscreen");
  const VkImageView views[2] = {impl_->color.view.get(), impl_->depth.view.get()};
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = impl_->renderPass.get();
  fi.attachmentCount = 2;
  fi.pAttachments = views;
  fi.width = uint32_t(width);
  fi.height = uint32_t(height);
  fi.layers = 1;
  VkFramebuffer fb;
  vk::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer (offscreen)");
  impl_->framebuffer = FramebufferHandle(dev, fb);

  impl_->pipelines = std::make_unique<ScenePipelines>(c, impl_->renderPass.get());
  impl_->readback = vk::Buffer::create(c, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       vk::MemoryUse::Readback, "render.readback");
}

OffscreenRenderer::~OffscreenRenderer() = default;

Image OffscreenRenderer::render(const Scene& scene, const Camera& camera) {
  draw(scene, camera, true);
  Image img;
  img.width = width_;
  img.height = height_;
  img.rgba.resize(size_t(width_) * height_ * 4);
  impl_->readback.download(std::as_writable_bytes(std::span<uint8_t>(img.rgba)));
  return img;
}

void OffscreenRenderer::renderOnly(const Scene& scene, const Camera& camera) { draw(scene, camera, false); }

void OffscreenRenderer::draw(const Scene& scene, const Camera& camera, bool readback) {
  vk::Context& c = *ctx_;
  // Overlay geometry lives for this frame only.
  vk::Buffer lines, markers;
  auto upload = [&](const std::vector<OverlayVertex>& v, const char* label) {
    vk::Buffer b = vk::Buffer::create(c, v.size() * sizeof(OverlayVertex),
                                      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      vk::MemoryUse::Upload, label);
    b.uploadSpan(std::span<const OverlayVertex>(v));
    return b;
  };
  if (!scene.lines.empty()) lines = upload(scene.lines, "render.lines");
  if (!scene.markers.empty()) markers = upload(scene.markers, "render.markers");

  vk::OneShot shot(c);
  VkCommandBuffer cmd = shot.cmd();
  if (scene.prepare) scene.prepare(cmd);
  VkClearValue clears[2];
  clears[0].color = {{scene.background.r, scene.background.g, scene.background.b, 0.0f}};
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  bi.renderPass = impl_->renderPass.get();
  bi.framebuffer = impl_->framebuffer.get();
  bi.renderArea = {{0, 0}, {uint32_t(width_), uint32_t(height_)}};
  bi.clearValueCount = 2;
  bi.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
  OverlayDraw overlay;
  overlay.lines = lines.handle();
  overlay.lineVertexCount = uint32_t(scene.lines.size());
  overlay.markers = markers.handle();
  overlay.markerVertexCount = uint32_t(scene.markers.size());
  impl_->pipelines->record(cmd, scene.meshes, overlay, camera, {uint32_t(width_), uint32_t(height_)});
  vkCmdEndRenderPass(cmd);
  if (readback) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {uint32_t(width_), uint32_t(height_), 1};
    vkCmdCopyImageToBuffer(cmd, impl_->color.image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           impl_->readback.handle(), 1, &region);
  }
  shot.submitAndWait();  // appends the barrier that makes the copy visible to the host
}

void addPolyline(std::vector<OverlayVertex>& out, const std::vector<glm::dvec3>& points, const glm::vec4& color) {
  for (size_t i = 0; i + 1 < points.size(); ++i)
    for (const glm::dvec3& p : {points[i], points[i + 1]})
      out.push_back({{float(p.x), float(p.y), float(p.z)}, {0.0f, 0.0f}, {color.r, color.g, color.b, color.a}});
}

void addMarker(std::vector<OverlayVertex>& out, const glm::dvec3& p, float sizePx, const glm::vec4& color) {
  const float h = 0.5f * sizePx;
  const float corners[6][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, -h}, {h, h}, {-h, h}};
  for (const auto& o : corners)
    out.push_back({{float(p.x), float(p.y), float(p.z)}, {o[0], o[1]}, {color.r, color.g, color.b, color.a}});
}

void addWidePolyline(std::vector<OverlayVertex>& out, const std::vector<glm::dvec3>& points, float widthPx,
                     const glm::vec4& color, const Camera& camera, int width, int height) {
  const float half = 0.5f * widthPx;
  const auto vertex = [&](const glm::dvec3& p, const glm::vec2& o) {
    out.push_back({{float(p.x), float(p.y), float(p.z)}, {o.x, o.y}, {color.r, color.g, color.b, color.a}});
  };
  for (size_t i = 0; i + 1 < points.size(); ++i) {
    const glm::dvec3 a = camera.toPixel(points[i], width, height), b = camera.toPixel(points[i + 1], width, height);
    const glm::dvec2 along(b.x - a.x, b.y - a.y);
    const double length = glm::length(along);
    if (length == 0.0) continue;  // the join markers cover it
    const glm::vec2 across = glm::vec2(-along.y / length, along.x / length) * half;
    const glm::dvec3 &p = points[i], &q = points[i + 1];
    vertex(p, -across), vertex(q, -across), vertex(q, across);
    vertex(p, -across), vertex(q, across), vertex(p, across);
  }
  for (const glm::dvec3& p : points) addMarker(out, p, widthPx, color);
}

}  // namespace shapespline::render

#include <shapespline/render/renderer.h>

#include <shapespline/gpu/tessellator.h>
#include "shaders/render_overlay_frag.h"
#include "shaders/render_overlay_vert.h"
#include "shaders/render_surface_frag.h"
#include "shaders/render_surface_vert.h"
#include <shapespline/vk/error.h>
#include <shapespline/vk/handle.h>
#include <shapespline/vk/pipeline_cache.h>
#include <shapespline/vk/submit.h>

#include <glm/gtc/type_ptr.hpp>

#include <array>
#include <cstring>
#include <stdexcept>
#include <string>

namespace shapespline::render {
namespace tl = gpu::tess_layout;

using ImageHandle = vk::Handle<VkImage, VkDevice, vkDestroyImage>;
using ImageViewHandle = vk::Handle<VkImageView, VkDevice, vkDestroyImageView>;
using RenderPassHandle = vk::Handle<VkRenderPass, VkDevice, vkDestroyRenderPass>;
using FramebufferHandle = vk::Handle<VkFramebuffer, VkDevice, vkDestroyFramebuffer>;

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

struct Attachment {
  vk::MemoryHandle memory;  // freed after the image (declared first)
  ImageHandle image;
  ImageViewHandle view;
};

Attachment makeAttachment(vk::Context& ctx, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                          int width, int height) {
  VkDevice dev = ctx.device();
  Attachment a;
  VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ii.imageType = VK_IMAGE_TYPE_2D;
  ii.format = format;
  ii.extent = {uint32_t(width), uint32_t(height), 1};
  ii.mipLevels = 1;
  ii.arrayLayers = 1;
  ii.samples = VK_SAMPLE_COUNT_1_BIT;
  ii.tiling = VK_IMAGE_TILING_OPTIMAL;
  ii.usage = usage;
  ii.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage image;
  vk::check(vkCreateImage(dev, &ii, nullptr, &image), "vkCreateImage (render attachment)");
  a.image = ImageHandle(dev, image);
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(dev, image, &req);
  const uint32_t type = ctx.findMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkMemoryAllocateInfo mi{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mi.allocationSize = req.size;
  mi.memoryTypeIndex = type == UINT32_MAX ? ctx.findMemoryType(req.memoryTypeBits, 0) : type;
  VkDeviceMemory mem;
  vk::check(vkAllocateMemory(dev, &mi, nullptr, &mem), "vkAllocateMemory (render attachment)");
  a.memory = vk::MemoryHandle(dev, mem);
  vk::check(vkBindImageMemory(dev, image, mem, 0), "vkBindImageMemory (render attachment)");
  VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vi.image = image;
  vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vi.format = format;
  vi.subresourceRange = {aspect, 0, 1, 0, 1};
  VkImageView view;
  vk::check(vkCreateImageView(dev, &vi, nullptr, &view), "vkCreateImageView (render attachment)");
  a.view = ImageViewHandle(dev, view);
  return a;
}

VkFormat depthFormat(const vk::Context& ctx) {
  for (VkFormat f : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32, VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D16_UNORM}) {
    VkFormatProperties p;
    vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), f, &p);
    if (p.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
  }
  throw std::runtime_error("no depth attachment format on device '" + ctx.deviceName() + "'");
}

vk::ShaderModuleHandle shaderModule(VkDevice dev, std::span<const uint32_t> code, const char* what) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = code.size_bytes();
  ci.pCode = code.data();
  VkShaderModule m;
  vk::check(vkCreateShaderModule(dev, &ci, nullptr, &m), what);
  return vk::ShaderModuleHandle(dev, m);
}

}  // namespace

struct OffscreenRenderer::Impl {
  Attachment color, depth;
  RenderPassHandle renderPass;
  FramebufferHandle framebuffer;
  vk::PipelineLayoutHandle layout;
  vk::PipelineHandle surface, wire, overlayLines, overlayTris;
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
  const VkFormat df = depthFormat(c);
  impl_->color = makeAttachment(c, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                VK_IMAGE_ASPECT_COLOR_BIT, width, height);
  impl_->depth = makeAttachment(c, df, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, width, height);

  // Render pass: clear both, the colour ends in TRANSFER_SRC for the readback copy.
  VkAttachmentDescription att[2] = {};
  att[0].format = kColorFormat;
  att[0].samples = VK_SAMPLE_COUNT_1_BIT;
  att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  att[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  att[1] = att[0];
  att[1].format = df;
  att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference colorRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &colorRef;
  sub.pDepthStencilAttachment = &depthRef;
  // In: the previous frame's readback copy / depth use must finish before this frame's writes.
  // Out: colour writes -> the transfer that copies the image to the readback buffer.
  VkSubpassDependency deps[2] = {};
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  deps[0].dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT;
  deps[0].srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  deps[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  deps[1].srcSubpass = 0;
  deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  rp.attachmentCount = 2;
  rp.pAttachments = att;
  rp.subpassCount = 1;
  rp.pSubpasses = &sub;
  rp.dependencyCount = 2;
  rp.pDependencies = deps;
  VkRenderPass pass;
  vk::check(vkCreateRenderPass(dev, &rp, nullptr, &pass), "vkCreateRenderPass (offscreen)");
  impl_->renderPass = RenderPassHandle(dev, pass);
  const VkImageView views[2] = {impl_->color.view.get(), impl_->depth.view.get()};
  VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fi.renderPass = pass;
  fi.attachmentCount = 2;
  fi.pAttachments = views;
  fi.width = uint32_t(width);
  fi.height = uint32_t(height);
  fi.layers = 1;
  VkFramebuffer fb;
  vk::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer (offscreen)");
  impl_->framebuffer = FramebufferHandle(dev, fb);

  const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(tl::RenderPush)};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &range;
  VkPipelineLayout layout;
  vk::check(vkCreatePipelineLayout(dev, &li, nullptr, &layout), "vkCreatePipelineLayout (render)");
  impl_->layout = vk::PipelineLayoutHandle(dev, layout);

  const auto surfVert = shaderModule(dev, render_surface_vert, "vkCreateShaderModule (render_surface.vert)");
  const auto surfFrag = shaderModule(dev, render_surface_frag, "vkCreateShaderModule (render_surface.frag)");
  const auto ovVert = shaderModule(dev, render_overlay_vert, "vkCreateShaderModule (render_overlay.vert)");
  const auto ovFrag = shaderModule(dev, render_overlay_frag, "vkCreateShaderModule (render_overlay.frag)");

  const VkVertexInputBindingDescription meshBinding = gpu::SurfaceTessellator::vertexBinding(0);
  const auto meshAttrs = gpu::SurfaceTessellator::vertexAttributes(0, 0);
  const VkVertexInputBindingDescription ovBinding{0, tl::kOverlayVertexStride, VK_VERTEX_INPUT_RATE_VERTEX};
  const std::array<VkVertexInputAttributeDescription, 3> ovAttrs{{{0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
                                                                  {1, 0, VK_FORMAT_R32G32_SFLOAT, 12},
                                                                  {2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, 20}}};
  auto makePipeline = [&](VkShaderModule vs, VkShaderModule fs, bool mesh, VkPrimitiveTopology topo, const char* label) {
    VkPipelineShaderStageCreateInfo stages[2] = {};
    stages[0].sType = stages[1].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
    stages[0].module = vs;
    stages[0].pName = "main";
    stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[1].module = fs;
    stages[1].pName = "main";
    VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vi.vertexBindingDescriptionCount = 1;
    vi.pVertexBindingDescriptions = mesh ? &meshBinding : &ovBinding;
    vi.vertexAttributeDescriptionCount = 3;
    vi.pVertexAttributeDescriptions = mesh ? meshAttrs.data() : ovAttrs.data();
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = topo;
    const VkViewport viewport{0.0f, 0.0f, float(width), float(height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {uint32_t(width), uint32_t(height)}};
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.pViewports = &viewport;
    vp.scissorCount = 1;
    vp.pScissors = &scissor;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = VK_POLYGON_MODE_FILL;
    rs.cullMode = VK_CULL_MODE_NONE;  // open surfaces show both sides
    rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = VK_TRUE;
    ds.depthWriteEnable = VK_TRUE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
    VkPipelineColorBlendAttachmentState blend{};
    blend.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                           VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    cb.attachmentCount = 1;
    cb.pAttachments = &blend;
    VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gi.stageCount = 2;
    gi.pStages = stages;
    gi.pVertexInputState = &vi;
    gi.pInputAssemblyState = &ia;
    gi.pViewportState = &vp;
    gi.pRasterizationState = &rs;
    gi.pMultisampleState = &ms;
    gi.pDepthStencilState = &ds;
    gi.pColorBlendState = &cb;
    gi.layout = layout;
    gi.renderPass = pass;
    VkPipeline p;
    vk::check(vkCreateGraphicsPipelines(dev, c.pipelineCache().handle(), 1, &gi, nullptr, &p), label);
    return vk::PipelineHandle(dev, p);
  };
  impl_->surface = makePipeline(surfVert.get(), surfFrag.get(), true, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                                "vkCreateGraphicsPipelines (surface)");
  impl_->wire = makePipeline(surfVert.get(), surfFrag.get(), true, VK_PRIMITIVE_TOPOLOGY_LINE_LIST,
                             "vkCreateGraphicsPipelines (wireframe)");
  impl_->overlayLines = makePipeline(ovVert.get(), ovFrag.get(), false, VK_PRIMITIVE_TOPOLOGY_LINE_LIST,
                                     "vkCreateGraphicsPipelines (overlay lines)");
  impl_->overlayTris = makePipeline(ovVert.get(), ovFrag.get(), false, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                                    "vkCreateGraphicsPipelines (overlay markers)");
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

  tl::RenderPush pc{};
  const glm::mat4 vp = camera.viewProj();
  std::memcpy(pc.viewProj, glm::value_ptr(vp), sizeof(pc.viewProj));
  pc.eye[0] = camera.eye.x;
  pc.eye[1] = camera.eye.y;
  pc.eye[2] = camera.eye.z;
  pc.params[2] = float(width_);
  pc.params[3] = float(height_);
  const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  VkPipelineLayout layout = impl_->layout.get();

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
  const VkDeviceSize zero = 0;
  for (const MeshDraw& m : scene.meshes) {
    if (m.indexCount == 0) continue;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, impl_->surface.get());
    vkCmdBindVertexBuffers(cmd, 0, 1, &m.vertexBuffer, &zero);
    vkCmdBindIndexBuffer(cmd, m.indexBuffer, 0, VK_INDEX_TYPE_UINT32);
    pc.color[0] = m.color.r;
    pc.color[1] = m.color.g;
    pc.color[2] = m.color.b;
    pc.params[0] = 0.0f;
    pc.params[1] = 0.0f;
    vkCmdPushConstants(cmd, layout, stages, 0, sizeof(pc), &pc);
    vkCmdDrawIndexed(cmd, m.indexCount, 1, 0, 0, 0);
    if (m.wireIndexBuffer != VK_NULL_HANDLE && m.wireIndexCount > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, impl_->wire.get());
      vkCmdBindIndexBuffer(cmd, m.wireIndexBuffer, 0, VK_INDEX_TYPE_UINT32);
      pc.color[0] = m.wireColor.r;
      pc.color[1] = m.wireColor.g;
      pc.color[2] = m.wireColor.b;
      pc.params[0] = 1.0f;
      pc.params[1] = 2e-4f;
      vkCmdPushConstants(cmd, layout, stages, 0, sizeof(pc), &pc);
      vkCmdDrawIndexed(cmd, m.wireIndexCount, 1, 0, 0, 0);
    }
  }
  pc.params[0] = 2.0f;
  pc.params[1] = 1e-3f;
  if (lines.handle()) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, impl_->overlayLines.get());
    const VkBuffer b = lines.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &b, &zero);
    vkCmdPushConstants(cmd, layout, stages, 0, sizeof(pc), &pc);
    vkCmdDraw(cmd, uint32_t(scene.lines.size()), 1, 0, 0);
  }
  if (markers.handle()) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, impl_->overlayTris.get());
    const VkBuffer b = markers.handle();
    vkCmdBindVertexBuffers(cmd, 0, 1, &b, &zero);
    pc.params[1] = 2e-3f;
    vkCmdPushConstants(cmd, layout, stages, 0, sizeof(pc), &pc);
    vkCmdDraw(cmd, uint32_t(scene.markers.size()), 1, 0, 0);
  }
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

}  // namespace shapespline::render

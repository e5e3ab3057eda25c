#include <shapespline/render/scene_pipelines.h>

#include <shapespline/gpu/tessellator.h>
#include "shaders/render_overlay_frag.h"
#include "shaders/render_overlay_vert.h"
#include "shaders/render_surface_frag.h"
#include "shaders/render_surface_vert.h"
#include <shapespline/vk/error.h>
#include <shapespline/vk/pipeline_cache.h>

#include <glm/gtc/type_ptr.hpp>

#include <array>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

namespace shapespline::render {
namespace tl = gpu::tess_layout;

namespace {

constexpr VkShaderStageFlags kPushStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

// RenderPush.params: x the mode (tess_layout.h), y the depth pull that lets lines win the depth test.
constexpr float kModeShaded = 0.0f, kModeWire = 1.0f, kModeOverlay = 2.0f;
constexpr float kWirePull = 2e-4f, kLinePull = 1e-3f, kMarkerPull = 2e-3f;

vk::ShaderModuleHandle shaderModule(VkDevice dev, std::span<const uint32_t> code, const char* what) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = code.size_bytes();
  ci.pCode = code.data();
  VkShaderModule m;
  vk::check(vkCreateShaderModule(dev, &ci, nullptr, &m), what);
  return vk::ShaderModuleHandle(dev, m);
}

}  // namespace

RenderPassHandle makeColorDepthPass(vk::Context& ctx, VkFormat color, VkFormat depth, VkImageLayout colorFinalLayout,
                                    VkPipelineStageFlags colorInStages, const char* label) {
  VkAttachmentDescription att[2] = {};
  att[0].format = color;
  att[0].samples = VK_SAMPLE_COUNT_1_BIT;
  att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  att[0].finalLayout = colorFinalLayout;
  att[1] = att[0];
  att[1].format = depth;
  att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference colorRef{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkAttachmentReference depthRef{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &colorRef;
  sub.pDepthStencilAttachment = &depthRef;
  // In: earlier work on the colour image (colorInStages) and the previous depth writes finish before
  // this pass writes. Out: colour writes -> a TRANSFER read.
  VkSubpassDependency deps[2] = {};
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[0].srcStageMask = colorInStages | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
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
  vk::check(vkCreateRenderPass(ctx.device(), &rp, nullptr, &pass), (std::string("vkCreateRenderPass (") + label + ")").c_str());
  return RenderPassHandle(ctx.device(), pass);
}

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

VkFormat depthAttachmentFormat(const vk::Context& ctx) {
  for (VkFormat f : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32, VK_FORMAT_D24_UNORM_S8_UINT, VK_FORMAT_D16_UNORM}) {
    VkFormatProperties p;
    vkGetPhysicalDeviceFormatProperties(ctx.physicalDevice(), f, &p);
    if (p.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
  }
  throw std::runtime_error("no depth attachment format on device '" + ctx.deviceName() + "'");
}

ScenePipelines::ScenePipelines(vk::Context& c, VkRenderPass pass) {
  VkDevice dev = c.device();
  const VkPushConstantRange range{kPushStages, 0, sizeof(tl::RenderPush)};
  VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  li.pushConstantRangeCount = 1;
  li.pPushConstantRanges = &range;
  VkPipelineLayout layout;
  vk::check(vkCreatePipelineLayout(dev, &li, nullptr, &layout), "vkCreatePipelineLayout (render)");
  layout_ = vk::PipelineLayoutHandle(dev, layout);

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
  auto makePipeline = [&](VkShaderModule vs, VkShaderModule fs, bool mesh, VkPrimitiveTopology topo,
                          VkPolygonMode polygonMode, const char* label) {
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
    // Viewport and scissor are dynamic: set by record() for the target's extent.
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = 1;
    vp.scissorCount = 1;
    const VkDynamicState dynamic[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = 2;
    dy.pDynamicStates = dynamic;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.polygonMode = polygonMode;
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
    gi.pDynamicState = &dy;
    gi.layout = layout;
    gi.renderPass = pass;
    VkPipeline p;
    vk::check(vkCreateGraphicsPipelines(dev, c.pipelineCache().handle(), 1, &gi, nullptr, &p), label);
    return vk::PipelineHandle(dev, p);
  };
  surface_ = makePipeline(surfVert.get(), surfFrag.get(), true, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                          VK_POLYGON_MODE_FILL, "vkCreateGraphicsPipelines (surface)");
  wire_ = makePipeline(surfVert.get(), surfFrag.get(), true, VK_PRIMITIVE_TOPOLOGY_LINE_LIST, VK_POLYGON_MODE_FILL,
                       "vkCreateGraphicsPipelines (wireframe)");
  if (c.supportsFillModeNonSolid())
    lineFill_ = makePipeline(surfVert.get(), surfFrag.get(), true, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                             VK_POLYGON_MODE_LINE, "vkCreateGraphicsPipelines (triangle wireframe)");
  overlayLines_ = makePipeline(ovVert.get(), ovFrag.get(), false, VK_PRIMITIVE_TOPOLOGY_LINE_LIST,
                               VK_POLYGON_MODE_FILL, "vkCreateGraphicsPipelines (overlay lines)");
  overlayTris_ = makePipeline(ovVert.get(), ovFrag.get(), false, VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
                              VK_POLYGON_MODE_FILL, "vkCreateGraphicsPipelines (overlay markers)");
}

ScenePipelines::~ScenePipelines() = default;

void ScenePipelines::record(VkCommandBuffer cmd, const std::vector<MeshDraw>& meshes, const OverlayDraw& overlay,
                            const Camera& camera, VkExtent2D extent) const {
  const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, extent};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);

  tl::RenderPush pc{};
  const glm::mat4 vp = camera.viewProj();
  std::memcpy(pc.viewProj, glm::value_ptr(vp), sizeof(pc.viewProj));
  pc.eye[0] = camera.eye.x;
  pc.eye[1] = camera.eye.y;
  pc.eye[2] = camera.eye.z;
  pc.params[2] = float(extent.width);
  pc.params[3] = float(extent.height);
  VkPipelineLayout layout = layout_.get();
  auto push = [&](const glm::vec3& colour, float mode, float pull) {
    pc.color[0] = colour.r;
    pc.color[1] = colour.g;
    pc.color[2] = colour.b;
    pc.params[0] = mode;
    pc.params[1] = pull;
    vkCmdPushConstants(cmd, layout, kPushStages, 0, sizeof(pc), &pc);
  };
  const VkDeviceSize zero = 0;
  for (const MeshDraw& m : meshes) {
    const bool indirect = m.indirectBuffer != VK_NULL_HANDLE;
    const bool triangles = indirect || m.indexCount > 0;
    const bool lines = m.wireIndexBuffer != VK_NULL_HANDLE && m.wireIndexCount > 0;
    if (!triangles && !lines) continue;
    auto drawTriangles = [&] {
      if (indirect) {
        vkCmdDrawIndexedIndirect(cmd, m.indirectBuffer, m.indirectOffset, 1, sizeof(VkDrawIndexedIndirectCommand));
      } else {
        vkCmdDrawIndexed(cmd, m.indexCount, 1, m.firstIndex, 0, 0);
      }
    };
    vkCmdBindVertexBuffers(cmd, 0, 1, &m.vertexBuffer, &zero);
    if (triangles) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, surface_.get());
      vkCmdBindIndexBuffer(cmd, m.indexBuffer, 0, VK_INDEX_TYPE_UINT32);
      push(m.color, kModeShaded, 0.0f);
      drawTriangles();
    }
    if (lines) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, wire_.get());
      vkCmdBindIndexBuffer(cmd, m.wireIndexBuffer, 0, VK_INDEX_TYPE_UINT32);
      push(m.wireColor, kModeWire, kWirePull);
      vkCmdDrawIndexed(cmd, m.wireIndexCount, 1, m.wireFirstIndex, 0, 0);
    } else if (triangles && m.wireframe && triangleWireframe()) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, lineFill_.get());
      push(m.wireColor, kModeWire, kWirePull);
      drawTriangles();
    }
  }
  const glm::vec3 none(0.0f);  // overlay vertices carry their own colour
  if (overlay.lines != VK_NULL_HANDLE && overlay.lineVertexCount > 0) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, overlayLines_.get());
    vkCmdBindVertexBuffers(cmd, 0, 1, &overlay.lines, &zero);
    push(none, kModeOverlay, kLinePull);
    vkCmdDraw(cmd, overlay.lineVertexCount, 1, 0, 0);
  }
  if (overlay.markers != VK_NULL_HANDLE && overlay.markerVertexCount > 0) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, overlayTris_.get());
    vkCmdBindVertexBuffers(cmd, 0, 1, &overlay.markers, &zero);
    push(none, kModeOverlay, kMarkerPull);
    vkCmdDraw(cmd, overlay.markerVertexCount, 1, 0, 0);
  }
}

}  // namespace shapespline::render

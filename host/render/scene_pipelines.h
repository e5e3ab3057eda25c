#pragma once
// ScenePipelines: the one place of the graphics pipelines that draw a Scene (shaded surface, its
// wireframe, overlay lines and markers) with one pipeline layout and the RenderPush constants of
// shaders/tess_layout.h. Created for a caller's render pass (subpass 0: one colour and one depth
// attachment, one sample) with dynamic viewport and scissor, so one set serves every image size:
// OffscreenRenderer records into its offscreen pass, the viewer (host/viewer) into its swapchain pass.
#include <shapespline/render/camera.h>
#include <shapespline/render/renderer.h>
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <vector>

namespace shapespline::render {

// Overlay vertex buffers of one frame (line list and marker triangles, OverlayVertex layout).
struct OverlayDraw {
  VkBuffer lines = VK_NULL_HANDLE;
  uint32_t lineVertexCount = 0;
  VkBuffer markers = VK_NULL_HANDLE;
  uint32_t markerVertexCount = 0;
};

// The best depth attachment format of the device (D32 first); throws std::runtime_error when none.
VkFormat depthAttachmentFormat(const vk::Context& ctx);

using ImageHandle = vk::Handle<VkImage, VkDevice, vkDestroyImage>;
using ImageViewHandle = vk::Handle<VkImageView, VkDevice, vkDestroyImageView>;
using RenderPassHandle = vk::Handle<VkRenderPass, VkDevice, vkDestroyRenderPass>;
using FramebufferHandle = vk::Handle<VkFramebuffer, VkDevice, vkDestroyFramebuffer>;

// A device-local 2-D image of one mip level and layer with its view (colour or depth attachment).
struct Attachment {
  vk::MemoryHandle memory;  // freed after the image (declared first)
  ImageHandle image;
  ImageViewHandle view;
};
Attachment makeAttachment(vk::Context& ctx, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                          int width, int height);

// A one-subpass render pass that clears one colour and one depth attachment; the colour ends in
// colorFinalLayout and its writes are made visible to a later TRANSFER read (readback or
// screenshot). `colorInStages`: the stages of earlier work on the colour image the pass waits for
// (the readback copy, or the swapchain acquire at COLOR_ATTACHMENT_OUTPUT).
RenderPassHandle makeColorDepthPass(vk::Context& ctx, VkFormat color, VkFormat depth, VkImageLayout colorFinalLayout,
                                    VkPipelineStageFlags colorInStages, const char* label);

class ScenePipelines {
 public:
  // Throws VulkanError. The context must outlive the pipelines.
  ScenePipelines(vk::Context& ctx, VkRenderPass renderPass);
  ~ScenePipelines();
  ScenePipelines(const ScenePipelines&) = delete;
  ScenePipelines& operator=(const ScenePipelines&) = delete;

  // MeshDraw::wireframe can draw the mesh's own triangles as lines (polygonMode LINE, needs the
  // device's fillModeNonSolid). Without it such a mesh draws no wireframe; a wireIndexBuffer
  // (render/painter.h, triangleEdges) always works.
  bool triangleWireframe() const { return lineFill_.get() != VK_NULL_HANDLE; }

  // Inside the render pass: viewport and scissor over `extent`, the meshes (each shaded, then its
  // wireframe), then the overlay lines and markers, all seen by `camera`.
  void record(VkCommandBuffer cmd, const std::vector<MeshDraw>& meshes, const OverlayDraw& overlay,
              const Camera& camera, VkExtent2D extent) const;

 private:
  vk::PipelineLayoutHandle layout_;
  vk::PipelineHandle surface_, wire_, lineFill_, overlayLines_, overlayTris_;
};

}  // namespace shapespline::render

#pragma once
// Swapchain: a VkSwapchainKHR of one surface with its image views, a depth attachment, the render
// pass the viewer draws in (clear colour and depth; colour ends in PRESENT_SRC) and one framebuffer
// per image. recreate() after a resize or VK_ERROR_OUT_OF_DATE_KHR keeps the render pass (the
// format does not change), so pipelines made for it stay valid.
#include <shapespline/render/scene_pipelines.h>
#include <shapespline/vk/context.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <vector>

namespace shapespline::viewer {

class Swapchain {
 public:
  // Throws DisplayError when the context's queue cannot present to `surface`.
  Swapchain(vk::Context& ctx, VkSurfaceKHR surface, VkExtent2D extent);
  ~Swapchain();
  Swapchain(const Swapchain&) = delete;
  Swapchain& operator=(const Swapchain&) = delete;

  // Waits for the device to be idle, then rebuilds images, depth and framebuffers for `extent`
  // (clamped to what the surface allows).
  void recreate(VkExtent2D extent);

  VkSwapchainKHR handle() const { return swapchain_; }
  VkRenderPass renderPass() const { return renderPass_.get(); }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  uint32_t imageCount() const { return uint32_t(images_.size()); }
  uint32_t minImageCount() const { return minImageCount_; }
  VkImage image(uint32_t i) const { return images_[i]; }
  VkFramebuffer framebuffer(uint32_t i) const { return framebuffers_[i].get(); }
  // The images were created with TRANSFER_SRC (screenshots); false where the surface refuses it.
  bool canReadBack() const { return readable_; }

 private:
  void build(VkExtent2D extent);

  vk::Context& ctx_;
  VkSurfaceKHR surface_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkColorSpaceKHR colorSpace_ = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR;
  VkFormat depthFormat_ = VK_FORMAT_UNDEFINED;
  VkPresentModeKHR presentMode_ = VK_PRESENT_MODE_FIFO_KHR;
  uint32_t minImageCount_ = 2;
  bool readable_ = false;
  render::RenderPassHandle renderPass_;
  VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
  VkExtent2D extent_{};
  std::vector<VkImage> images_;
  std::vector<render::ImageViewHandle> views_;
  render::Attachment depth_;
  std::vector<render::FramebufferHandle> framebuffers_;
};

}  // namespace shapespline::viewer

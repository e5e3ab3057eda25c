#include <shapespline/viewer/swapchain.h>

#include <shapespline/viewer/errors.h>
#include <shapespline/vk/error.h>

#include <algorithm>

namespace shapespline::viewer {
namespace {

VkSurfaceFormatKHR chooseFormat(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  uint32_t n = 0;
  vk::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, nullptr), "vkGetPhysicalDeviceSurfaceFormatsKHR");
  std::vector<VkSurfaceFormatKHR> formats(n);
  vk::check(vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface, &n, formats.data()), "vkGetPhysicalDeviceSurfaceFormatsKHR");
  if (formats.empty()) throw DisplayError("the window surface offers no image format");
  // UNORM as the offscreen renderer (R8G8B8A8_UNORM): the same colours in a screenshot as in `render`.
  for (VkFormat want : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
    for (const VkSurfaceFormatKHR& f : formats)
      if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) return f;
  return formats[0];
}

VkPresentModeKHR choosePresentMode(VkPhysicalDevice pd, VkSurfaceKHR surface) {
  uint32_t n = 0;
  vk::check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, nullptr), "vkGetPhysicalDeviceSurfacePresentModesKHR");
  std::vector<VkPresentModeKHR> modes(n);
  vk::check(vkGetPhysicalDeviceSurfacePresentModesKHR(pd, surface, &n, modes.data()),
            "vkGetPhysicalDeviceSurfacePresentModesKHR");
  // MAILBOX: no tearing and no wait for a vertical blank a virtual display (Xvfb) may never have.
  if (std::find(modes.begin(), modes.end(), VK_PRESENT_MODE_MAILBOX_KHR) != modes.end()) return VK_PRESENT_MODE_MAILBOX_KHR;
  return VK_PRESENT_MODE_FIFO_KHR;  // always supported
}

}  // namespace

Swapchain::Swapchain(vk::Context& ctx, VkSurfaceKHR surface, VkExtent2D extent) : ctx_(ctx), surface_(surface) {
  VkBool32 supported = VK_FALSE;
  vk::check(vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), surface, &supported),
            "vkGetPhysicalDeviceSurfaceSupportKHR");
  if (!supported)
    throw DisplayError("queue family " + std::to_string(ctx.queueFamily()) + " of '" + ctx.deviceName() +
                       "' cannot present to the window");
  const VkSurfaceFormatKHR f = chooseFormat(ctx.physicalDevice(), surface);
  format_ = f.format;
  colorSpace_ = f.colorSpace;
  presentMode_ = choosePresentMode(ctx.physicalDevice(), surface);
  depthFormat_ = render::depthAttachmentFormat(ctx);

  // The acquire semaphore is waited at COLOR_ATTACHMENT_OUTPUT, so the layout transition waits for
  // it there; the one depth buffer is reused by every frame in flight (the previous frame's depth
  // writes finish first). Colour writes are visible to a screenshot copy (TRANSFER) or present.
  renderPass_ = render::makeColorDepthPass(ctx, format_, depthFormat_, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                                           VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, "viewer");
  build(extent);
}

Swapchain::~Swapchain() {
  framebuffers_.clear();
  views_.clear();
  if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
}

void Swapchain::recreate(VkExtent2D extent) {
  ctx_.waitIdle();
  build(extent);
}

void Swapchain::build(VkExtent2D wanted) {
  VkDevice dev = ctx_.device();
  VkSurfaceCapabilitiesKHR caps;
  vk::check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physicalDevice(), surface_, &caps),
            "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  if (caps.currentExtent.width != UINT32_MAX) {
    extent_ = caps.currentExtent;
  } else {
    extent_.width = std::clamp(wanted.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent_.height = std::clamp(wanted.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  minImageCount_ = std::max(2u, caps.minImageCount + 1);
  if (caps.maxImageCount > 0) minImageCount_ = std::min(minImageCount_, caps.maxImageCount);
  readable_ = (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT) != 0;

  VkSwapchainCreateInfoKHR ci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  ci.surface = surface_;
  ci.minImageCount = minImageCount_;
  ci.imageFormat = format_;
  ci.imageColorSpace = colorSpace_;
  ci.imageExtent = extent_;
  ci.imageArrayLayers = 1;
  ci.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (readable_ ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
  ci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  ci.preTransform = caps.currentTransform;
  ci.compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                          ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                          : VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
  ci.presentMode = presentMode_;
  ci.clipped = VK_TRUE;
  ci.oldSwapchain = swapchain_;
  VkSwapchainKHR next;
  vk::check(vkCreateSwapchainKHR(dev, &ci, nullptr, &next), "vkCreateSwapchainKHR");
  framebuffers_.clear();
  views_.clear();
  if (swapchain_ != VK_NULL_HANDLE) vkDestroySwapchainKHR(dev, swapchain_, nullptr);
  swapchain_ = next;

  uint32_t n = 0;
  vk::check(vkGetSwapchainImagesKHR(dev, swapchain_, &n, nullptr), "vkGetSwapchainImagesKHR");
  images_.resize(n);
  vk::check(vkGetSwapchainImagesKHR(dev, swapchain_, &n, images_.data()), "vkGetSwapchainImagesKHR");
  depth_ = render::makeAttachment(ctx_, depthFormat_, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                  VK_IMAGE_ASPECT_DEPTH_BIT, int(extent_.width), int(extent_.height));
  for (VkImage image : images_) {
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format_;
    vi.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkImageView view;
    vk::check(vkCreateImageView(dev, &vi, nullptr, &view), "vkCreateImageView (swapchain)");
    views_.emplace_back(dev, view);
    const VkImageView attachments[2] = {view, depth_.view.get()};
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = renderPass_.get();
    fi.attachmentCount = 2;
    fi.pAttachments = attachments;
    fi.width = extent_.width;
    fi.height = extent_.height;
    fi.layers = 1;
    VkFramebuffer fb;
    vk::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer (swapchain)");
    framebuffers_.emplace_back(dev, fb);
  }
}

}  // namespace shapespline::viewer

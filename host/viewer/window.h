#pragma once
// Window: GLFW (initialised once per process) and one window without a client API, for a Vulkan
// surface. Throws DisplayError when there is no display or GLFW has no Vulkan support.
#include <vulkan/vulkan_core.h>

#include <string>
#include <vector>

struct GLFWwindow;

namespace shapespline::viewer {

class Window {
 public:
  Window(int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* handle() const { return window_; }
  bool shouldClose() const;
  // The framebuffer in pixels (0 x 0 while minimised).
  VkExtent2D framebufferSize() const;

  // What a Vulkan context needs to present to this window's display.
  std::vector<std::string> requiredInstanceExtensions() const;
  static bool canPresent(VkInstance instance, VkPhysicalDevice device, uint32_t queueFamily);
  // A surface of this window; the caller destroys it (vkDestroySurfaceKHR) before the instance.
  VkSurfaceKHR createSurface(VkInstance instance) const;

 private:
  GLFWwindow* window_ = nullptr;
};

}  // namespace shapespline::viewer

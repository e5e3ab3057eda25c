#include <shapespline/viewer/window.h>

#include <shapespline/viewer/errors.h>
#include <shapespline/vk/error.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <string>

namespace shapespline::viewer {
namespace {

std::string glfwReason() {
  const char* text = nullptr;
  const int code = glfwGetError(&text);
  return text ? std::string(text) : "GLFW error " + std::to_string(code);
}

}  // namespace

Window::Window(int width, int height, const std::string& title) {
  if (!glfwInit())
    throw DisplayError("cannot open a window: " + glfwReason() + " (is DISPLAY or WAYLAND_DISPLAY set?)");
  if (!glfwVulkanSupported()) {
    glfwTerminate();
    throw DisplayError("cannot open a window: GLFW finds no Vulkan loader");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string reason = glfwReason();
    glfwTerminate();
    throw DisplayError("cannot open a window: " + reason);
  }
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }

VkExtent2D Window::framebufferSize() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
}

std::vector<std::string> Window::requiredInstanceExtensions() const {
  uint32_t count = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&count);
  if (!names) throw DisplayError("GLFW cannot present with Vulkan here: " + glfwReason());
  return {names, names + count};
}

bool Window::canPresent(VkInstance instance, VkPhysicalDevice device, uint32_t queueFamily) {
  uint32_t count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, nullptr);
  std::vector<VkQueueFamilyProperties> families(count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families.data());
  return queueFamily < count && (families[queueFamily].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
         glfwGetPhysicalDevicePresentationSupport(instance, device, queueFamily) == GLFW_TRUE;
}

VkSurfaceKHR Window::createSurface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  vk::check(glfwCreateWindowSurface(instance, window_, nullptr, &surface), "glfwCreateWindowSurface");
  return surface;
}

}  // namespace shapespline::viewer

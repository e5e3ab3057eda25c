#pragma once
// Gui: Dear ImGui (1.86) on the viewer's window and render pass through ImGui's GLFW and Vulkan
// backends: one context per viewer, its descriptor pool and font texture.
#include <shapespline/vk/context.h>
#include <shapespline/vk/handle.h>

#include <vulkan/vulkan_core.h>

#include <cstdint>

struct GLFWwindow;

namespace shapespline::viewer {

class Gui {
 public:
  Gui(GLFWwindow* window, vk::Context& ctx, VkRenderPass renderPass, uint32_t minImageCount, uint32_t imageCount);
  ~Gui();
  Gui(const Gui&) = delete;
  Gui& operator=(const Gui&) = delete;

  // Starts a frame: input from GLFW, then ImGui::NewFrame (widgets follow).
  void newFrame();
  // Ends the frame (ImGui::Render) and records its draw lists; inside the render pass.
  void record(VkCommandBuffer cmd);
  // After a swapchain recreation.
  void setMinImageCount(uint32_t minImageCount);
  // ImGui wants the mouse (the cursor is over a widget): the scene ignores it then.
  bool wantsMouse() const;

 private:
  vk::DescriptorPoolHandle pool_;
};

}  // namespace shapespline::viewer

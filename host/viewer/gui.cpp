#include <shapespline/viewer/gui.h>

#include <shapespline/vk/error.h>
#include <shapespline/vk/submit.h>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include <stdexcept>

namespace shapespline::viewer {
namespace {

void checkImGuiVk(VkResult result) { vk::check(result, "ImGui Vulkan backend"); }

}  // namespace

Gui::Gui(GLFWwindow* window, vk::Context& ctx, VkRenderPass renderPass, uint32_t minImageCount, uint32_t imageCount) {
  // The backend allocates one combined image sampler set (the font texture).
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4};
  VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pi.maxSets = 4;
  pi.poolSizeCount = 1;
  pi.pPoolSizes = &size;
  VkDescriptorPool pool;
  vk::check(vkCreateDescriptorPool(ctx.device(), &pi, nullptr, &pool), "vkCreateDescriptorPool (ImGui)");
  pool_ = vk::DescriptorPoolHandle(ctx.device(), pool);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working directory
  ImGui::StyleColorsDark();
  if (!ImGui_ImplGlfw_InitForVulkan(window, true)) throw std::runtime_error("ImGui_ImplGlfw_InitForVulkan failed");
  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = ctx.instance();
  info.PhysicalDevice = ctx.physicalDevice();
  info.Device = ctx.device();
  info.QueueFamily = ctx.queueFamily();
  info.Queue = ctx.queue();
  info.PipelineCache = VK_NULL_HANDLE;
  info.DescriptorPool = pool;
  info.Subpass = 0;
  info.MinImageCount = minImageCount;
  info.ImageCount = imageCount;
  info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
  info.CheckVkResultFn = checkImGuiVk;
  if (!ImGui_ImplVulkan_Init(&info, renderPass)) throw std::runtime_error("ImGui_ImplVulkan_Init failed");
  vk::runOneShot(ctx, [](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
}

Gui::~Gui() {
  ImGui_ImplVulkan_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
}

void Gui::newFrame() {
  ImGui_ImplVulkan_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void Gui::record(VkCommandBuffer cmd) {
  ImGui::Render();
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
}

void Gui::setMinImageCount(uint32_t minImageCount) { ImGui_ImplVulkan_SetMinImageCount(minImageCount); }

bool Gui::wantsMouse() const { return ImGui::GetIO().WantCaptureMouse; }

}  // namespace shapespline::viewer

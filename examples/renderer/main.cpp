// Headless integration example: the application creates its own Vulkan instance, device (one
// graphics + compute queue), vertex/index buffers and command buffer; shapespline adopts the device,
// tessellates an α-EB surface into the application's buffers inside the application's command
// buffer, a λ change is re-tessellated the same way, and the frames are drawn (here with the
// library's OffscreenRenderer on the same adopted device) and written as PNG.
//
//   renderer_example [MODEL.json] [out_prefix]     (defaults: examples/models/surface_aeb.json, frame)
#include <shapespline/core/surface.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/gpu/tessellator.h>
#include <shapespline/io/model_json.h>
#include <shapespline/io/png_writer.h>
#include <shapespline/render/renderer.h>
#include <shapespline/vk/context.h>

#include <vulkan/vulkan_core.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: " + std::to_string(r));
}

struct AppBuffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
};

AppBuffer createBuffer(VkPhysicalDevice phys, VkDevice dev, VkDeviceSize size, VkBufferUsageFlags usage) {
  AppBuffer b;
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = size;
  bi.usage = usage;
  check(vkCreateBuffer(dev, &bi, nullptr, &b.buffer), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(dev, b.buffer, &req);
  VkPhysicalDeviceMemoryProperties mp;
  vkGetPhysicalDeviceMemoryProperties(phys, &mp);
  uint32_t type = 0;
  while (type < mp.memoryTypeCount &&
         !((req.memoryTypeBits >> type) & 1u && mp.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
    ++type;
  if (type == mp.memoryTypeCount) throw std::runtime_error("no device-local memory type");
  VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  ai.allocationSize = req.size;
  ai.memoryTypeIndex = type;
  check(vkAllocateMemory(dev, &ai, nullptr, &b.memory), "vkAllocateMemory");
  check(vkBindBufferMemory(dev, b.buffer, b.memory, 0), "vkBindBufferMemory");
  return b;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shapespline;
  const std::string modelPath = argc > 1 ? argv[1] : "examples/models/surface_aeb.json";
  const std::string prefix = argc > 2 ? argv[2] : "frame";
  try {
    // ---- The application's Vulkan objects ------------------------------------------------------
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "renderer_example";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ii{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ii.pApplicationInfo = &app;
    VkInstance instance;
    check(vkCreateInstance(&ii, nullptr, &instance), "vkCreateInstance");
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    if (n == 0) {
      std::fprintf(stderr, "renderer_example: no Vulkan device\n");
      return 0;  // nothing to show, not an error (CI without a driver)
    }
    std::vector<VkPhysicalDevice> phys(n);
    vkEnumeratePhysicalDevices(instance, &n, phys.data());
    VkPhysicalDevice pd = phys[0];
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> fams(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, fams.data());
    uint32_t family = 0;
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    while (family < qn && (fams[family].queueFlags & need) != need) ++family;
    if (family == qn) throw std::runtime_error("no graphics + compute queue family");
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    const VkPhysicalDeviceFeatures features{};  // fp32 tessellation needs no optional feature
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    di.pEnabledFeatures = &features;
    VkDevice device;
    check(vkCreateDevice(pd, &di, nullptr, &device), "vkCreateDevice");
    VkQueue queue;
    vkGetDeviceQueue(device, family, 0, &queue);
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = family;
    VkCommandPool pool;
    check(vkCreateCommandPool(device, &pi, nullptr, &pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ci{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ci.commandPool = pool;
    ci.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ci.commandBufferCount = 1;
    VkCommandBuffer cmd;
    check(vkAllocateCommandBuffers(device, &ci, &cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence;
    check(vkCreateFence(device, &fi, nullptr, &fence), "vkCreateFence");

    {
      // ---- shapespline on the adopted device ---------------------------------------------------
      auto ctx = vk::Context::adopt(instance, pd, device, family, queue, &features);
      const auto model = std::get<SurfaceModel>(io::loadModelFile(modelPath));
      gpu::GpuSurface surface(ctx, Surface::create(model), Precision::Float);  // net uploaded once
      gpu::SurfaceTessellator tess(ctx, surface, gpu::SurfaceTessellator::uniformRates(surface, 16));

      // The application's vertex and index buffers, sized by the tessellator.
      const AppBuffer vb = createBuffer(pd, device, tess.vertexBytes(), gpu::kTessVertexBufferUsage);
      const AppBuffer ib = createBuffer(pd, device, tess.indexBytes(), gpu::kTessIndexBufferUsage);
      const gpu::TessTargets targets{vb.buffer, 0, ib.buffer, 0};
      // Vertex input for the application's own pipeline (here the library renderer uses the same).
      const VkVertexInputBindingDescription binding = gpu::SurfaceTessellator::vertexBinding(0);
      std::printf("vertex stride %u bytes, %u vertices, %u indices\n", binding.stride, tess.vertexCount(), tess.indexCount());

      render::OffscreenRenderer renderer(ctx, 640, 480);
      const render::Camera cam = render::Camera::frame({-0.5, -0.5, -1.5}, {4.5, 4.5, 2.5}, 35.0, 30.0, 640.0 / 480.0);
      const double lambdas[] = {0.0, -3.0};
      for (int frame = 0; frame < 2; ++frame) {
        surface.setLambda(lambdas[frame]);  // PARAMS only; the net is not re-uploaded
        // Tessellate inside the application's command buffer; record() ends with the barrier that
        // vertex input needs, so a draw could follow in the same command buffer.
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer");
        tess.record(cmd, targets);
        check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.commandBufferCount = 1;
        si.pCommandBuffers = &cmd;
        check(vkQueueSubmit(queue, 1, &si, fence), "vkQueueSubmit");
        check(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
        check(vkResetFences(device, 1, &fence), "vkResetFences");
        check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");

        render::Scene scene;
        scene.meshes.push_back({vb.buffer, ib.buffer, tess.indexCount()});
        const render::Image img = renderer.render(scene, cam);
        const std::string out = prefix + "_" + std::to_string(frame) + ".png";
        io::writePng(out, img.width, img.height, img.rgba);
        std::printf("lambda %g -> %s\n", lambdas[frame], out.c_str());
      }
      vkDeviceWaitIdle(device);
      for (const AppBuffer& b : {vb, ib}) {
        vkDestroyBuffer(device, b.buffer, nullptr);
        vkFreeMemory(device, b.memory, nullptr);
      }
    }  // the library's objects go before the device they were created on
    vkDestroyFence(device, fence, nullptr);
    vkDestroyCommandPool(device, pool, nullptr);
    vkDestroyDevice(device, nullptr);
    vkDestroyInstance(instance, nullptr);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "renderer_example: %s\n", e.what());
    return 1;
  }
}

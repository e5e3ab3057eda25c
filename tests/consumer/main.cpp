// shapespline_consumer: uses the installed shapespline package the way an application does.
//  * core + io: a surface from a model file and a curve built in memory, evaluated on the CPU (fp64);
//  * gpu: the application creates its own VkInstance / VkDevice, shapespline adopts them
//    (vk::Context::adopt), and the GPU evaluators' fp32 results are checked against core;
//  * sampling: a Session on the same context evaluates the curve on the GPU (device required).
// Without a Vulkan device the GPU part is skipped with a message (exit 0).
//
//   shapespline_consumer SURFACE_MODEL.json       exit 0: results agree, 1: they do not, 2: error
#include <shapespline/core/curve.h>
#include <shapespline/core/model.h>
#include <shapespline/core/surface.h>
#include <shapespline/gpu/evaluator.h>
#include <shapespline/gpu/gpu_model.h>
#include <shapespline/io/model_json.h>
#include <shapespline/sampling/session.h>
#include <shapespline/version.h>
#include <shapespline/vk/context.h>

#include <vulkan/vulkan_core.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace {

using namespace shapespline;

// fp32 GPU against fp64 CPU: a fraction of the control net's extent (points), and of the
// derivative's own size (partials).
constexpr double kPointTol = 1e-4;
constexpr double kDerivTol = 1e-3;

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: VkResult " + std::to_string(r));
}

double extent(const std::vector<glm::dvec3>& pts) {
  glm::dvec3 lo = pts.front(), hi = pts.front();
  for (const auto& p : pts) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  return glm::length(hi - lo);
}

// An α-EB curve made in memory (the model of examples/models/open_aeb.json).
CurveModel memoryCurve() {
  CurveModel m;
  m.family.construction = Construction::AlphaEB;
  m.family.degree = 5;
  m.family.lambda = -2.5;
  m.dimension = 2;
  m.points = {{0, 0, 0}, {1, 2, 0}, {3, 3, 0}, {5, 1, 0}, {6, 4, 0}, {8, 3, 0}};
  m.alpha = {0.5, 0.25, 1, 0.75, 0.5, 0.625};
  return m;
}

std::vector<double> spread(std::pair<double, double> range, int n) {
  std::vector<double> t;
  for (int i = 0; i < n; ++i) t.push_back(range.first + (range.second - range.first) * i / (n - 1));
  return t;
}

int failures = 0;

void compare(const char* what, size_t index, const glm::dvec3& cpu, const glm::dvec3& gpu, double tol) {
  const double err = glm::length(gpu - cpu);
  if (err > tol) {
    ++failures;
    std::printf("MISMATCH %s[%zu]: cpu (%.17g, %.17g, %.17g) gpu (%.9g, %.9g, %.9g) error %.3g > %.3g\n", what,
                index, cpu.x, cpu.y, cpu.z, gpu.x, gpu.y, gpu.z, err, tol);
  }
}

// The application's Vulkan objects: instance, a device with one compute queue. Null instance when
// there is no driver or no device.
struct AppVulkan {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  uint32_t family = 0;
  VkQueue queue = VK_NULL_HANDLE;
  VkPhysicalDeviceFeatures enabled{};
  std::string why;  // when there is no device

  AppVulkan() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "shapespline_consumer";
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo ii{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ii.pApplicationInfo = &app;
    if (const VkResult r = vkCreateInstance(&ii, nullptr, &instance); r != VK_SUCCESS) {
      instance = VK_NULL_HANDLE;
      why = "vkCreateInstance returned " + std::to_string(r) + " (no Vulkan driver)";
      return;
    }
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(instance, &n, devices.data());
    for (VkPhysicalDevice pd : devices) {
      VkPhysicalDeviceProperties props;
      vkGetPhysicalDeviceProperties(pd, &props);
      if (props.apiVersion < VK_API_VERSION_1_1) continue;
      uint32_t qn = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, nullptr);
      std::vector<VkQueueFamilyProperties> fams(qn);
      vkGetPhysicalDeviceQueueFamilyProperties(pd, &qn, fams.data());
      for (uint32_t f = 0; f < qn; ++f) {
        if (fams[f].queueFlags & VK_QUEUE_COMPUTE_BIT) {
          physical = pd;
          family = f;
          break;
        }
      }
      if (physical != VK_NULL_HANDLE) break;
    }
    if (physical == VK_NULL_HANDLE) {
      why = devices.empty() ? "no Vulkan device" : "no Vulkan 1.1 device with a compute queue";
      return;
    }
    VkPhysicalDeviceFeatures supported;
    vkGetPhysicalDeviceFeatures(physical, &supported);
    enabled.shaderFloat64 = supported.shaderFloat64;
    enabled.shaderInt64 = supported.shaderInt64;
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    di.pEnabledFeatures = &enabled;
    check(vkCreateDevice(physical, &di, nullptr, &device), "vkCreateDevice");
    vkGetDeviceQueue(device, family, 0, &queue);
  }
  ~AppVulkan() {
    if (device != VK_NULL_HANDLE) vkDestroyDevice(device, nullptr);
    if (instance != VK_NULL_HANDLE) vkDestroyInstance(instance, nullptr);
  }
  AppVulkan(const AppVulkan&) = delete;
  AppVulkan& operator=(const AppVulkan&) = delete;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: shapespline_consumer SURFACE_MODEL.json\n");
    return 2;
  }
  try {
    std::printf("shapespline %s (commit %s)\n", SHAPESPLINE_VERSION_STRING, SHAPESPLINE_GIT_COMMIT);

    // ---- core + io: CPU fp64 ------------------------------------------------------------------
    const Surface surface = Surface::create(std::get<SurfaceModel>(io::loadModelFile(argv[1])));
    const Curve curve = Curve::create(memoryCurve());
    std::vector<std::pair<double, double>> uv;
    for (double U : spread(surface.parameterRangeU(), 4))
      for (double V : spread(surface.parameterRangeV(), 4)) uv.emplace_back(U, V);
    const std::vector<double> us = spread(curve.parameterRange(), 9);
    std::vector<SurfacePoint> cpuS;
    for (const auto& [U, V] : uv) cpuS.push_back(surface.evaluateAt(U, V));
    std::vector<CurvePoint> cpuC;
    for (double u : us) cpuC.push_back(curve.evaluateAt(u));
    const SurfacePoint& mid = cpuS[5];
    std::printf("cpu: surface %s %dx%d, S(%g, %g) = (%.6f, %.6f, %.6f); curve %s, C(%g) = (%.6f, %.6f)\n",
                std::string(constructionName(surface.model().family.construction)).c_str(), surface.model().rows,
                surface.model().cols, uv[5].first, uv[5].second, mid.point.x, mid.point.y, mid.point.z,
                std::string(constructionName(curve.model().family.construction)).c_str(), us[4], cpuC[4].point.x,
                cpuC[4].point.y);

    // ---- gpu on the application's own device ----------------------------------------------------
    AppVulkan app;
    if (app.device == VK_NULL_HANDLE) {
      std::printf("gpu: skipped: %s\n", app.why.c_str());
      return 0;
    }
    {
      auto ctx = vk::Context::adopt(app.instance, app.physical, app.device, app.family, app.queue, &app.enabled);
      std::printf("gpu: adopted device \"%s\" (owns handles: %s)\n", ctx->deviceName().c_str(),
                  ctx->ownsHandles() ? "yes" : "no");
      if (ctx->ownsHandles()) throw std::runtime_error("adopted context claims to own the device");

      gpu::GpuSurface gpuSurface(ctx, surface, Precision::Float);
      gpu::SurfaceEvaluator surfaceEval(ctx, Precision::Float);
      const auto gotS = surfaceEval.evaluateListAt(gpuSurface, uv);
      const double extS = extent(surface.controlPoints());
      for (size_t k = 0; k < uv.size(); ++k) {
        compare("surface point", k, cpuS[k].point, gotS[k].point, kPointTol * extS);
        compare("surface du", k, cpuS[k].du, gotS[k].du, kDerivTol * (extS + glm::length(cpuS[k].du)));
        compare("surface dv", k, cpuS[k].dv, gotS[k].dv, kDerivTol * (extS + glm::length(cpuS[k].dv)));
      }

      gpu::GpuCurve gpuCurve(ctx, curve, Precision::Float);
      gpu::CurveEvaluator curveEval(ctx, Precision::Float);
      const auto gotC = curveEval.evaluateListAt(gpuCurve, us);
      const double extC = extent(curve.model().points);
      for (size_t k = 0; k < us.size(); ++k) {
        compare("curve point", k, cpuC[k].point, gotC[k].point, kPointTol * extC);
        compare("curve d1", k, cpuC[k].d1, gotC[k].d1, kDerivTol * (extC + glm::length(cpuC[k].d1)));
      }
      sampling::Session session(ctx);
      std::vector<sampling::CurveQuery> queries;
      for (double u : us) queries.push_back({true, 0, 0.0, u});
      const auto viaLayer = session.evaluate(curve, {sampling::DeviceKind::Auto, Precision::Float, true}, queries);
      if (!viaLayer.report.gpu) throw std::runtime_error("sampling::Session did not use the adopted device");
      for (size_t k = 0; k < us.size(); ++k) {
        compare("sampling curve point", k, cpuC[k].point, viaLayer.points[k].point, kPointTol * extC);
      }
      std::printf("gpu: S(%g, %g) = (%.6f, %.6f, %.6f); C(%g) = (%.6f, %.6f)\n", uv[5].first, uv[5].second,
                  gotS[5].point.x, gotS[5].point.y, gotS[5].point.z, us[4], gotC[4].point.x, gotC[4].point.y);
      ctx->waitIdle();
    }  // every shapespline object is gone before the application destroys its device
    if (failures) {
      std::printf("FAILED: %d GPU values differ from core\n", failures);
      return 1;
    }
    std::printf("ok: %zu surface and %zu curve samples, GPU fp32 agrees with core fp64\n", uv.size(), us.size());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "shapespline_consumer: error: %s\n", e.what());
    return 2;
  }
}

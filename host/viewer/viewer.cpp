#include <shapespline/viewer/viewer.h>

#include <shapespline/io/png_writer.h>
#include <shapespline/render/scene_pipelines.h>
#include <shapespline/viewer/gui.h>
#include <shapespline/viewer/orbit_camera.h>
#include <shapespline/viewer/part_subject.h>
#include <shapespline/viewer/subject.h>
#include <shapespline/viewer/surface_subject.h>
#include <shapespline/viewer/swapchain.h>
#include <shapespline/viewer/window.h>
#include <shapespline/vk/buffer.h>
#include <shapespline/vk/error.h>
#include <shapespline/vk/submit.h>

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <span>

namespace shapespline::viewer {
namespace {

using Clock = std::chrono::steady_clock;
using Kind = ScriptCommand::Kind;
using SemaphoreHandle = vk::Handle<VkSemaphore, VkDevice, vkDestroySemaphore>;
using SurfaceHandle = vk::Handle<VkSurfaceKHR, VkInstance, vkDestroySurfaceKHR>;

constexpr uint32_t kFramesInFlight = 2;
constexpr double kDegreesPerPixel = 0.4;   // left drag
constexpr double kZoomPerWheelStep = 0.9;  // one wheel notch towards the target
constexpr double kStatsSeconds = 0.25;     // triangle count read back at most this often
const glm::vec3 kBackground{1.0f, 1.0f, 1.0f};

// The controls every subject has (its own are in the subject); applied between frames.
struct Controls {
  float tolerancePx = 1.0f;
  bool wireframe = false;
  bool panel = true;  // the ImGui panel is drawn
};

// Makes the subject once the device and the pipelines exist.
using SubjectFactory = std::function<std::unique_ptr<Subject>(std::shared_ptr<vk::Context>, const render::ScenePipelines&)>;

std::string messagesText(const std::vector<vk::ValidationMessage>& messages) {
  std::string text;
  for (const vk::ValidationMessage& m : messages) text += "\n  [" + m.id + "] " + m.text;
  return text;
}

class Viewer {
 public:
  Viewer(std::shared_ptr<vk::Context> ctx, Window& window, const SubjectFactory& makeSubject, const ViewerOptions& options)
      : ctx_(std::move(ctx)),
        window_(window),
        options_(options),
        surface_(ctx_->instance(), window.createSurface(ctx_->instance())),
        swapchain_(*ctx_, surface_.get(), window.framebufferSize()),
        pipelines_(*ctx_, swapchain_.renderPass()),
        gui_(window.handle(), *ctx_, swapchain_.renderPass(), swapchain_.minImageCount(), swapchain_.imageCount()),
        subject_(makeSubject(ctx_, pipelines_)),
        orbit_(subject_->bounds().first, subject_->bounds().second) {
    createFrames();
    lastFrame_ = lastStats_ = Clock::now();
  }

  ~Viewer() {
    if (ctx_) ctx_->waitIdle();
  }

  void run() {
    size_t next = 0;  // the next script command
    int framesLeft = 0;
    std::string shot;
    const std::vector<ScriptCommand> none;
    const std::vector<ScriptCommand>& script = options_.script ? *options_.script : none;
    while (!window_.shouldClose()) {
      glfwPollEvents();
      // Script commands run between frames until one asks for frames (frames, screenshot) or quits.
      while (framesLeft == 0 && next < script.size()) {
        const ScriptCommand& c = script[next++];
        if (c.kind == Kind::Quit) return;
        if (c.kind == Kind::Frames) framesLeft = int(c.numbers[0]);
        if (c.kind == Kind::Screenshot) {
          shot = c.name;
          framesLeft = 1;
        }
        execute(c);
      }
      const VkExtent2D size = window_.framebufferSize();
      if (size.width == 0 || size.height == 0) {  // minimised: nothing to draw into
        glfwWaitEvents();
        continue;
      }
      const bool capture = framesLeft == 1 && !shot.empty();
      if (!drawFrame(capture ? &shot : nullptr)) continue;  // swapchain recreated: draw again
      if (capture) shot.clear();
      if (framesLeft > 0) --framesLeft;
      checkValidation();
    }
  }

  uint64_t frames() const { return frameCount_; }
  uint64_t triangles() const { return triangles_; }
  double frameMs() const { return frameMs_; }

 private:
  struct Frame {
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    vk::FenceHandle done;
    SemaphoreHandle acquired;
  };

  void createFrames() {
    VkDevice dev = ctx_->device();
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;  // each frame re-records its buffer
    pi.queueFamilyIndex = ctx_->queueFamily();
    VkCommandPool pool;
    vk::check(vkCreateCommandPool(dev, &pi, nullptr, &pool), "vkCreateCommandPool (viewer)");
    pool_ = vk::CommandPoolHandle(dev, pool);
    for (Frame& f : frames_) {
      VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
      ai.commandPool = pool;
      ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      ai.commandBufferCount = 1;
      vk::check(vkAllocateCommandBuffers(dev, &ai, &f.cmd), "vkAllocateCommandBuffers (viewer)");
      VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
      fi.flags = VK_FENCE_CREATE_SIGNALED_BIT;
      VkFence fence;
      vk::check(vkCreateFence(dev, &fi, nullptr, &fence), "vkCreateFence (viewer)");
      f.done = vk::FenceHandle(dev, fence);
      f.acquired = makeSemaphore();
    }
    createPresentSemaphores();
  }

  SemaphoreHandle makeSemaphore() const {
    VkSemaphoreCreateInfo si{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VkSemaphore s;
    vk::check(vkCreateSemaphore(ctx_->device(), &si, nullptr, &s), "vkCreateSemaphore (viewer)");
    return SemaphoreHandle(ctx_->device(), s);
  }

  // One per swapchain image: a present may still wait on the semaphore of its image while a later
  // frame (another image) renders.
  void createPresentSemaphores() {
    rendered_.clear();
    for (uint32_t i = 0; i < swapchain_.imageCount(); ++i) rendered_.push_back(makeSemaphore());
  }

  void recreateSwapchain() {
    swapchain_.recreate(window_.framebufferSize());  // waits for the device to be idle
    createPresentSemaphores();
    gui_.setMinImageCount(swapchain_.minImageCount());
    readback_ = vk::Buffer();
  }

  View view() const {
    const VkExtent2D e = swapchain_.extent();
    return {orbit_.camera(int(e.width), int(e.height)), e};
  }

  // Brings the subject to its controls and to the common ones for the current view. Returns the
  // rule a value broke, or "".
  std::string applyControls() {
    const std::string error = subject_->apply(controls_.tolerancePx, view());
    applied_ = controls_;
    return error;
  }

  // A script line: sets what the widgets and the mouse set, through the same functions; the
  // subject's own commands go to the subject.
  void execute(const ScriptCommand& c) {
    auto fail = [&](const std::string& rule) { throw ScriptError(c.line, c.text, rule); };
    std::string notice;
    switch (c.kind) {
      case Kind::Pick: {
        const std::string picked = subject_->pick(c.numbers[0], c.numbers[1], view());
        if (picked.empty()) fail(subject_->pickMiss());
        notice = "picked " + picked;
        break;
      }
      case Kind::Orbit: orbit_.rotate(c.numbers[0], c.numbers[1]); break;
      case Kind::Pan: orbit_.pan(c.numbers[0], c.numbers[1], int(swapchain_.extent().height)); break;
      case Kind::Zoom: orbit_.zoom(c.numbers[0]); break;
      case Kind::Tolerance: controls_.tolerancePx = float(c.numbers[0]); break;
      case Kind::Wireframe: controls_.wireframe = c.on; break;
      case Kind::Panel: controls_.panel = c.on; break;
      case Kind::Frames:
      case Kind::Screenshot:
      case Kind::Quit: break;
      default: notice = subject_->execute(c, view());
    }
    if (const std::string error = applyControls(); !error.empty()) fail(error);
    if (!notice.empty() && !options_.quiet) std::fprintf(stderr, "shapespline: view: %s\n", notice.c_str());
  }

  // The mouse over the scene (not over the panel): left drag orbits, right or shift+left drag pans,
  // the wheel zooms, a left click without a drag picks.
  void handleMouse() {
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureMouse) return;
    const bool pan = ImGui::IsMouseDragging(ImGuiMouseButton_Right) ||
                     (io.KeyShift && ImGui::IsMouseDragging(ImGuiMouseButton_Left));
    if (pan) {
      orbit_.pan(io.MouseDelta.x, io.MouseDelta.y, int(swapchain_.extent().height));
    } else if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
      orbit_.rotate(-io.MouseDelta.x * kDegreesPerPixel, io.MouseDelta.y * kDegreesPerPixel);
    }
    if (io.MouseWheel != 0.0f) orbit_.zoom(std::pow(kZoomPerWheelStep, double(io.MouseWheel)));
    // A release that never moved beyond ImGui's drag threshold is a click.
    const float threshold = io.MouseDragThreshold;
    if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) && !io.KeyShift &&
        io.MouseDragMaxDistanceSqr[ImGuiMouseButton_Left] < threshold * threshold)
      subject_->pick(io.MousePos.x, io.MousePos.y, view());
  }

  void panel() {
    if (!controls_.panel) return;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    // The panel takes the size of its content (no label or widget clipped at any window size), with
    // sliders of a fixed width in font units and wrapped text no wider than the sliders' rows.
    ImGui::Begin("shapespline", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    const float em = ImGui::GetFontSize();
    ImGui::PushItemWidth(14 * em);
    ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 22 * em);
    ImVec2 contentMax(0, 0);  // the lower right corner of everything drawn, for panelBounds_
    const PanelNote note = [&] {
      const ImVec2 q = ImGui::GetItemRectMax();
      contentMax = ImVec2(std::max(contentMax.x, q.x), std::max(contentMax.y, q.y));
    };
    subject_->panelTitle(note);
    ImGui::Text("mesh: %s", subject_->meshName().c_str());
    note();
    ImGui::Text("frame %.2f ms, %llu triangles", frameMs_, static_cast<unsigned long long>(triangles_));
    note();
    ImGui::Separator();
    subject_->panelControls(note);
    ImGui::SliderFloat("tolerance (px)", &controls_.tolerancePx, 0.25f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    note();
    ImGui::BeginDisabled(!subject_->wireframeAvailable(pipelines_));
    ImGui::Checkbox("wireframe", &controls_.wireframe);
    note();
    ImGui::EndDisabled();
    subject_->panelToggles(note);
    if (!error_.empty()) {
      ImGui::TextWrapped("%s", error_.c_str());
      note();
    }
    ImGui::PopTextWrapPos();
    ImGui::PopItemWidth();
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    panelBounds_ = {true, pos, ImVec2(pos.x + size.x, pos.y + size.y), contentMax, ImGui::GetStyle().WindowPadding};
    ImGui::End();
  }

  void updateStats() {
    const Clock::time_point now = Clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - lastFrame_).count();
    lastFrame_ = now;
    // The first interval includes the start-up; the average starts with the second.
    if (frameCount_ == 2) frameMs_ = ms;
    if (frameCount_ > 2) frameMs_ = 0.9 * frameMs_ + 0.1 * ms;
    if (frameCount_ == 1 || std::chrono::duration<double>(now - lastStats_).count() >= kStatsSeconds) {
      triangles_ = subject_->triangleCount();  // may wait for idle: a few times a second only
      lastStats_ = now;
    }
  }

  // Records the copy of the presented image into readback_ (after the render pass; the image is
  // back in PRESENT_SRC afterwards).
  void recordCapture(VkCommandBuffer cmd, VkImage image) {
    const VkExtent2D e = swapchain_.extent();
    if (!readback_.handle())
      readback_ = vk::Buffer::create(*ctx_, VkDeviceSize(e.width) * e.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     vk::MemoryUse::Readback, "viewer.screenshot");
    auto transition = [&](VkImageLayout from, VkImageLayout to, VkAccessFlags srcAccess, VkAccessFlags dstAccess,
                          VkPipelineStageFlags src, VkPipelineStageFlags dst) {
      VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
      b.srcAccessMask = srcAccess;
      b.dstAccessMask = dstAccess;
      b.oldLayout = from;
      b.newLayout = to;
      b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
      b.image = image;
      b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
      vkCmdPipelineBarrier(cmd, src, dst, 0, 0, nullptr, 0, nullptr, 1, &b);
    };
    // The render pass's outgoing dependency already orders its colour writes before TRANSFER.
    transition(VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, 0, VK_ACCESS_TRANSFER_READ_BIT,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {e.width, e.height, 1};
    vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.handle(), 1, &region);
    transition(VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_ACCESS_TRANSFER_READ_BIT, 0,
               VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT);
    vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
  }

  void saveCapture(const std::string& name) {
    const VkExtent2D e = swapchain_.extent();
    std::vector<uint8_t> rgba(size_t(e.width) * e.height * 4);
    readback_.download(std::as_writable_bytes(std::span<uint8_t>(rgba)));
    if (swapchain_.format() == VK_FORMAT_B8G8R8A8_UNORM || swapchain_.format() == VK_FORMAT_B8G8R8A8_SRGB)
      for (size_t k = 0; k < rgba.size(); k += 4) std::swap(rgba[k], rgba[k + 2]);
    const std::filesystem::path path = options_.screenshotDir / name;
    io::writePng(path, int(e.width), int(e.height), rgba, false);
    if (panelBounds_.shown) savePanelBounds(path, e);
    if (!options_.quiet)
      std::fprintf(stderr, "shapespline: view: wrote %s (%u x %u, %llu triangles)\n", path.c_str(), e.width, e.height,
                   static_cast<unsigned long long>(subject_->triangleCount()));
  }

  // NAME.png's panel as NAME.panel.json: {"framebuffer": [w, h], "window": [x0, y0, x1, y1],
  // "content_max": [x, y], "padding": [x, y]} (pixels; ImGui's window padding inside its edges).
  void savePanelBounds(const std::filesystem::path& png, VkExtent2D e) const {
    const PanelBounds& b = panelBounds_;
    const nlohmann::json j = {{"framebuffer", {e.width, e.height}},
                              {"window", {b.windowMin.x, b.windowMin.y, b.windowMax.x, b.windowMax.y}},
                              {"content_max", {b.contentMax.x, b.contentMax.y}},
                              {"padding", {b.padding.x, b.padding.y}}};
    std::filesystem::path path = png;
    path.replace_extension(".panel.json");
    std::ofstream out(path);
    out << j.dump() << "\n";
    if (!out.flush()) throw std::runtime_error("cannot write " + path.string());
  }

  // One frame; `capture` names the screenshot to save of it. Returns false when the swapchain was
  // out of date and has been recreated (nothing drawn).
  bool drawFrame(const std::string* capture) {
    if (capture && !swapchain_.canReadBack())
      throw DisplayError("screenshot: the window surface does not allow reading its images (no TRANSFER_SRC usage)");
    const VkExtent2D want = window_.framebufferSize();
    const VkExtent2D have = swapchain_.extent();
    if (want.width != have.width || want.height != have.height) {
      recreateSwapchain();
      return false;
    }
    Frame& f = frames_[frameIndex_];
    VkDevice dev = ctx_->device();
    const VkFence fence = f.done.get();
    vk::check(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences (viewer frame)");

    uint32_t image = 0;
    const VkResult acquired = vkAcquireNextImageKHR(dev, swapchain_.handle(), UINT64_MAX, f.acquired.get(),
                                                    VK_NULL_HANDLE, &image);
    if (acquired == VK_ERROR_OUT_OF_DATE_KHR) {
      recreateSwapchain();
      return false;
    }
    if (acquired != VK_SUBOPTIMAL_KHR) vk::check(acquired, "vkAcquireNextImageKHR");

    gui_.newFrame();
    handleMouse();
    panelBounds_ = {};
    panel();
    if (const std::string error = applyControls(); !error.empty()) error_ = error;

    vk::check(vkResetFences(dev, 1, &fence), "vkResetFences (viewer frame)");
    VkCommandBuffer cmd = f.cmd;
    vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer (viewer frame)");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd, &bi), "vkBeginCommandBuffer (viewer frame)");
    const View frame = view();
    const VkExtent2D extent = frame.extent;
    subject_->record(cmd, frame);

    VkClearValue clears[2];
    clears[0].color = {{kBackground.r, kBackground.g, kBackground.b, 1.0f}};
    clears[1].depthStencil = {1.0f, 0};
    VkRenderPassBeginInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    rp.renderPass = swapchain_.renderPass();
    rp.framebuffer = swapchain_.framebuffer(image);
    rp.renderArea = {{0, 0}, extent};
    rp.clearValueCount = 2;
    rp.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &rp, VK_SUBPASS_CONTENTS_INLINE);
    pipelines_.record(cmd, subject_->meshes(applied_.wireframe), subject_->overlay(), frame.camera, extent);
    gui_.record(cmd);
    vkCmdEndRenderPass(cmd);
    if (capture) recordCapture(cmd, swapchain_.image(image));
    vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer (viewer frame)");

    const VkSemaphore wait = f.acquired.get(), signal = rendered_[image].get();
    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &wait;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &signal;
    VkResult presented;
    {
      std::lock_guard lock(ctx_->submitMutex());  // the queue is shared with the context's own submissions
      vk::check(vkQueueSubmit(ctx_->queue(), 1, &si, fence), "vkQueueSubmit (viewer frame)");
      VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
      pi.waitSemaphoreCount = 1;
      pi.pWaitSemaphores = &signal;
      pi.swapchainCount = 1;
      const VkSwapchainKHR sc = swapchain_.handle();
      pi.pSwapchains = &sc;
      pi.pImageIndices = &image;
      presented = vkQueuePresentKHR(ctx_->queue(), &pi);
    }
    frameIndex_ = (frameIndex_ + 1) % kFramesInFlight;
    ++frameCount_;
    if (capture) {
      vk::check(vkWaitForFences(dev, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences (screenshot)");
      saveCapture(*capture);
    }
    updateStats();
    if (presented == VK_ERROR_OUT_OF_DATE_KHR || presented == VK_SUBOPTIMAL_KHR) {
      recreateSwapchain();
    } else {
      vk::check(presented, "vkQueuePresentKHR");
    }
    return true;
  }

  void checkValidation() const {
    if (!options_.validation && !ctx_->validationEnabled()) return;
    const auto messages = ctx_->validationMessages();
    if (!messages.empty())
      throw ValidationFailure(std::to_string(messages.size()) + " Vulkan validation message(s):" + messagesText(messages));
  }

  std::shared_ptr<vk::Context> ctx_;
  Window& window_;
  const ViewerOptions& options_;
  SurfaceHandle surface_;
  Swapchain swapchain_;
  render::ScenePipelines pipelines_;
  Gui gui_;
  std::unique_ptr<Subject> subject_;  // after the pipelines it is made for, before the camera framing it
  OrbitCamera orbit_;
  Controls controls_, applied_;
  std::string error_;
  vk::CommandPoolHandle pool_;
  std::array<Frame, kFramesInFlight> frames_;
  std::vector<SemaphoreHandle> rendered_;
  uint32_t frameIndex_ = 0;
  vk::Buffer readback_;
  uint64_t frameCount_ = 0, triangles_ = 0;
  double frameMs_ = 0.0;
  Clock::time_point lastFrame_, lastStats_;
  // Where this frame's panel stands, in pixels: its window and the lower right corner of its content
  // (written beside a screenshot, so that a test can check that nothing is clipped).
  struct PanelBounds {
    bool shown = false;
    ImVec2 windowMin, windowMax, contentMax, padding;
  } panelBounds_;
};

void runViewer(const SubjectFactory& makeSubject, const ViewerOptions& options) {
  Window window(options.width, options.height, options.title);
  vk::ContextOptions co;
  co.validation = options.validation;
  co.instanceExtensions = window.requiredInstanceExtensions();
  co.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  co.queueFamilyFilter = Window::canPresent;
  std::shared_ptr<vk::Context> ctx;
  try {
    ctx = vk::Context::create(co);
  } catch (const vk::NoDeviceError& e) {
    throw DisplayError("no Vulkan device can draw into the window: " + e.reason());
  }
  {
    Viewer viewer(ctx, window, makeSubject, options);
    viewer.run();
    if (!options.quiet)
      std::fprintf(stderr, "shapespline: view: %llu frames, %.2f ms a frame, %llu triangles\n",
                   static_cast<unsigned long long>(viewer.frames()), viewer.frameMs(),
                   static_cast<unsigned long long>(viewer.triangles()));
  }
  // Destruction of the viewer's objects is covered too (the context's own teardown is not).
  if (options.validation || ctx->validationEnabled()) {
    const auto messages = ctx->validationMessages();
    if (!messages.empty())
      throw ValidationFailure(std::to_string(messages.size()) + " Vulkan validation message(s):" + messagesText(messages));
  }
}

}  // namespace

void runViewer(const SurfaceModel& model, const ViewerOptions& options) {
  runViewer(
      [&](std::shared_ptr<vk::Context> ctx, const render::ScenePipelines& pipelines) {
        return std::make_unique<SurfaceSubject>(std::move(ctx), model, Controls{}.tolerancePx,
                                                pipelines.triangleWireframe());
      },
      options);
}

void runViewer(part::Part part, const ViewerOptions& options) {
  runViewer(
      [&](std::shared_ptr<vk::Context> ctx, const render::ScenePipelines&) {
        return std::make_unique<PartSubject>(std::move(ctx), std::move(part));
      },
      options);
}

}  // namespace shapespline::viewer

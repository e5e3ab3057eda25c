#pragma once
// `shapespline view`: an interactive window on a surface model or a part (docs/viewer.md). A GLFW
// window with a Vulkan swapchain, an orbit camera and a Dear ImGui panel with the frame time and
// triangle count; what it shows is a Subject (subject.h): a surface tessellated on the GPU every
// frame for the camera, with λ, μ, per-point α and its control net, or a part meshed on the host,
// whose faces a click picks. Both take the pixel tolerance and the wireframe. A script (script.h)
// drives the same controls for tests and saves screenshots.
#include <shapespline/core/model.h>
#include <shapespline/part/part_model.h>
#include <shapespline/viewer/errors.h>
#include <shapespline/viewer/script.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace shapespline::viewer {

struct ViewerOptions {
  int width = 1280, height = 720;
  std::string title = "shapespline view";
  // Run these commands (in order, between frames) before handing over to the user; a script that
  // ends with `quit` closes the window.
  std::optional<std::vector<ScriptCommand>> script;
  std::filesystem::path screenshotDir = ".";
  // VK_LAYER_KHRONOS_validation on; any message ends the viewer with ValidationFailure (also when
  // SHAPESPLINE_VALIDATION=1 turned the layers on).
  bool validation = false;
  bool quiet = false;  // no progress lines on stderr
};

// Runs until the window closes or the script quits. Throws ScriptError (a script line that breaks a
// rule, e.g. an α out of (0, 1]), DisplayError, ValidationFailure, std::invalid_argument for a model
// the GPU tessellators do not take, vk::VulkanError / std::runtime_error otherwise.
void runViewer(const SurfaceModel& model, const ViewerOptions& options);
// A part, or one trimmed face (part::faceAsPart), meshed on the host (viewer/part_subject.h): the
// same window and controls, a click picks a face. Also std::invalid_argument for a part the mesher
// refuses (ModelError: crossing trim loops, a face without coedges).
void runViewer(part::Part part, const ViewerOptions& options);

}  // namespace shapespline::viewer

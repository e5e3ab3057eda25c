// `shapespline view MODEL`: the interactive viewer (host/viewer, docs/viewer.md). The command line
// only parses and maps errors; every window and Vulkan call is in the viewer library, which is
// built when GLFW and Dear ImGui were found at configure time.
#include <shapespline/cli/common.h>
#include <shapespline/cli/part_mesh_options.h>
#include <shapespline/io/output_set.h>

#ifdef SHAPESPLINE_HAS_VIEWER
#include <shapespline/viewer/viewer.h>
#endif

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <system_error>

namespace shapespline::cli {
namespace {

struct ViewArgs {
  std::string model, size = "1280x720", script, screenshotDir = ".";
  bool validation = false, quiet = false, screenshotDirGiven = false;
};

#ifdef SHAPESPLINE_HAS_VIEWER
void runView(const ViewArgs& a) {
  viewer::ViewerOptions o;
  std::tie(o.width, o.height) = parseImageSize(a.size, "--size", 64);
  o.validation = a.validation;
  o.quiet = a.quiet;
  o.screenshotDir = a.screenshotDir;
  try {
    if (!a.script.empty()) o.script = viewer::loadScript(a.script);
  } catch (const viewer::ScriptError& e) {
    throw InputError("--script", a.script, e.what());
  }
  const bool screenshots = o.script && std::any_of(o.script->begin(), o.script->end(), [](const auto& c) {
    return c.kind == viewer::ScriptCommand::Kind::Screenshot;
  });
  if (a.screenshotDirGiven && !screenshots)
    throw InputError("--screenshot-dir", a.screenshotDir, "does not apply without a --script that takes screenshots");
  // A screenshot may not replace a file the viewer reads (the model or the script).
  for (const auto& c : o.script.value_or(std::vector<viewer::ScriptCommand>{})) {
    if (c.kind != viewer::ScriptCommand::Kind::Screenshot) continue;
    const std::filesystem::path shot = o.screenshotDir / c.name;
    for (const auto& [what, input] : {std::pair{"MODEL", a.model}, std::pair{"--script", a.script}}) {
      if (io::sameFile(shot, input)) {
        throw InputError("--script", a.script,
                         "line " + std::to_string(c.line) + ": screenshot '" + shot.string() + "' is the same file as " +
                             what + " ('" + input + "'), which this command reads; give the screenshot another name");
      }
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(o.screenshotDir, ec);
  if (ec || !std::filesystem::is_directory(o.screenshotDir))
    throw InputError("--screenshot-dir", a.screenshotDir, "must be a folder that exists or can be created");
  // A part (`import`'s part.json) or a face with trim loops is shown as its mesh, trimmed.
  io::Model model;
  std::optional<part::Part> part = partToDraw(a.model, model);
  if (!part && !std::holds_alternative<SurfaceModel>(model))
    throw InputError("MODEL", a.model, "view draws surfaces and parts; draw curves with `shapespline render`");
  o.title = "shapespline view " + std::filesystem::path(a.model).filename().string();
  try {
    if (part) {
      viewer::runViewer(std::move(*part), o);
    } else {
      viewer::runViewer(std::get<SurfaceModel>(model), o);
    }
  } catch (const viewer::ScriptError& e) {
    throw InputError("--script", a.script, e.what());
  } catch (const viewer::DisplayError& e) {
    throw RuntimeError("display", "", e.what());
  } catch (const viewer::ValidationFailure& e) {
    throw RuntimeError("--validation", "", e.what());
  } catch (const std::invalid_argument& e) {
    throw InputError("MODEL", a.model, e.what());
  }
}
#else
void runView(const ViewArgs&) {
  throw RuntimeError("view", "", "this build has no viewer (configure found no libglfw3-dev or libimgui-dev)");
}
#endif

}  // namespace

void registerView(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* sub = app.add_subcommand(
      "view", "Open an interactive window on a surface model or a part (Vulkan swapchain, orbit camera, Dear ImGui controls).");
  sub->add_option("MODEL", args->model, "surface model file (docs/format.md), a trimmed face, or a part's part.json")->required();
  sub->add_option("--size", args->size, "window size WxH")->capture_default_str();
  sub->add_option("--script", args->script, "run the commands of this file (docs/viewer.md), e.g. for tests");
  sub->add_option("--screenshot-dir", args->screenshotDir, "folder of the script's screenshots")->capture_default_str();
  sub->add_flag("--validation", args->validation,
                "enable VK_LAYER_KHRONOS_validation and fail (exit 3) on any message (also SHAPESPLINE_VALIDATION=1)");
  addQuietFlag(sub, args->quiet, "no notices on stderr");
  sub->footer(kExitCodeHelp);
  sub->callback([args, sub] {
    args->screenshotDirGiven = sub->count("--screenshot-dir") > 0;
    runView(*args);
  });
}

}  // namespace shapespline::cli

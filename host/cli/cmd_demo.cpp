// `shapespline demo`: no input needed. Writes built-in example models (the same as
// examples/models/) and their samples as OBJ and SVG into ./shapespline-demo/, then a labelled
// contact sheet of what λ and α do (rendered on the Vulkan device, lavapipe will do), and prints the
// list and where to look first.
#include <shapespline/cli/cmd_render.h>
#include <shapespline/cli/cmd_sample.h>
#include <shapespline/cli/common.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/output_set.h>
#include <shapespline/io/png_writer.h>
#include <shapespline/render/painter.h>
#include <shapespline/vk/error.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <vector>

namespace shapespline::cli {
namespace {

constexpr const char* kButterfly = R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -1, "closed": true,
 "name": "butterfly", "comment": "closed butterfly-like alpha-EB curve; alpha = 1 at the body, tension in the wings",
 "points": [[0, 0.5], [1.5, 3], [4, 4.5], [5.5, 3], [4.5, 1], [2, 0], [4.5, -1.5], [5, -3.5], [3, -4], [1, -2],
            [0, -0.5], [-1, -2], [-3, -4], [-5, -3.5], [-4.5, -1.5], [-2, 0], [-4.5, 1], [-5.5, 3], [-4, 4.5], [-1.5, 3]],
 "alpha": [1, 0.5, 0.5, 0.5, 0.75, 1, 0.75, 0.5, 0.5, 0.5, 1, 0.5, 0.5, 0.5, 0.75, 1, 0.75, 0.5, 0.5, 0.5]}
)";

std::string openCurve(const std::string& alpha) {
  return R"({"kind": "curve", "construction": "alpha_eb", "degree": 5, "lambda": -2.5, "closed": false,
 "name": "open alpha-EB curve, alpha = )" + alpha + R"(",
 "points": [[0, 0], [1, 2], [3, 3], [5, 1], [6, 4], [8, 3]], "alpha": )" + alpha + "}\n";
}

std::string surface(const std::string& lambda) {
  return R"({"kind": "surface", "construction": "alpha_eb", "degree": 5, "lambda": )" + lambda +
         R"(, "closed": [false, false],
 "name": "alpha-EB surface, lambda = )" + lambda + R"(",
 "points": [[[0, 0, 0], [0, 1, 0.5], [0, 2, 0], [0, 3, -0.5], [0, 4, 0]],
            [[1, 0, 0.5], [1, 1, 1.5], [1, 2, 0.5], [1, 3, 0], [1, 4, 0.5]],
            [[2, 0, 0], [2, 1, 0.5], [2, 2, 2], [2, 3, 0.5], [2, 4, 0]],
            [[3, 0, -0.5], [3, 1, 0], [3, 2, 0.5], [3, 3, 1.5], [3, 4, 0.5]],
            [[4, 0, 0], [4, 1, 0.5], [4, 2, 0], [4, 3, 0.5], [4, 4, 0]]],
 "alpha": [[0.5, 0.5, 0.5, 0.5, 0.5], [0.5, 0.5, 0.5, 0.5, 0.5], [0.5, 0.5, 1, 0.5, 0.5],
           [0.5, 0.5, 0.5, 0.5, 0.5], [0.5, 0.5, 0.5, 0.5, 0.5]]}
)";
}

struct DemoArgs {
  std::string dir = "shapespline-demo", device = "cpu";
  bool quiet = false;
};

void writeDemo(const DemoArgs& a);

// The contact sheet's tiles: what each shape parameter does, on the demo's own models (written
// before the sheet), at values far enough apart to see. Curves overlay their values, a colour
// each (render --overlay); the surface, whose change is smaller than its size, is coloured by how
// far each point moves between two values (render --distance).
struct SheetTile {
  const char* model;  // in the demo folder
  const char* sweep;
  const char* title;
  bool distance;  // else an overlay
};
constexpr SheetTile kSheet[] = {
    {"open_aeb_alpha_0.25.json", "lambda=-15,-5,0,1", "lambda: the shape of an open curve", false},
    {"butterfly_aeb.json", "alpha=0.1,0.6,1", "alpha: the tension of a closed curve", false},
    {"surface_aeb_lambda_0.json", "lambda=1,-15", "alpha-EB surface, 4 x 4 wide", true},
    {"surface_aeb_lambda_0.json", "alpha=1,0.1", "alpha-EB surface, 4 x 4 wide", true},
};
constexpr int kSheetColumns = 2;
constexpr const char* kSheetSize = "480x360";  // of one tile
constexpr const char* kSheetSummary =
    "what lambda and alpha do to an open curve, a closed curve and a surface, the values in each legend";

void writeContactSheet(const std::string& dir, io::AtomicFile& png) {
  std::vector<render::Image> tiles;
  std::optional<render::Painter> painter;
  for (const SheetTile& t : kSheet) {
    RenderArgs r;
    r.model = (std::filesystem::path(dir) / t.model).string();
    r.size = kSheetSize;
    r.sweep = t.sweep;
    r.title = t.title;
    r.overlay = !t.distance;
    r.distance = t.distance;
    r.quiet = true;
    const RenderPlan plan = planRender(r);
    if (!painter) painter.emplace(plan.width, plan.height);
    for (render::Image& tile : renderTiles(r, plan, *painter)) tiles.push_back(std::move(tile));
  }
  const render::Image sheet = composeSheet(tiles, kSheetColumns);
  io::writePng(png, sheet.width, sheet.height, sheet.rgba, false);
}

void runDemo(const DemoArgs& a) {
  std::error_code ec;
  const bool created = std::filesystem::create_directories(a.dir, ec);
  if (ec) throw io::OutputPathError("--dir", a.dir, "cannot create the folder: " + ec.message());
  try {
    writeDemo(a);
  } catch (...) {
    if (created) std::filesystem::remove(a.dir, ec);  // only when empty: a folder this run made
    throw;
  }
}

void writeDemo(const DemoArgs& a) {
  struct Item {
    std::string name, text;
    bool surface;
  };
  std::vector<Item> items = {{"butterfly_aeb", kButterfly, false}};
  for (const char* alpha : {"0.25", "0.5", "1"}) items.push_back({std::string("open_aeb_alpha_") + alpha, openCurve(alpha), false});
  for (const char* lambda : {"-2", "0", "1"}) items.push_back({std::string("surface_aeb_lambda_") + lambda, surface(lambda), true});

  // Every model and every sample file is one output set: all of them appear, or none changes (a
  // full disk halfway leaves the folder as it was). Each job reads its model from the model's
  // temporary file, and records the model's final path.
  io::OutputSet outputs;
  std::vector<std::string> written;
  for (const auto& it : items) {
    const std::string base = (std::filesystem::path(a.dir) / it.name).string();
    io::AtomicFile& model = outputs.add(base + ".json", "--dir");
    model.write(it.text);
    model.flushToTemp();
    written.push_back(base + ".json");
    SampleArgs s;
    s.model = model.tempPath().string();
    s.modelName = base + ".json";
    s.device = a.device;
    s.quiet = true;
    if (it.surface) s.grid = "24x24"; else s.samples = "48";
    std::string summary;
    for (const char* ext : {".obj", ".svg"}) {
      if (it.surface && std::string(ext) == ".svg") continue;
      s.out = base + ext;
      sampleInto(s, outputs, summary);
      written.push_back(s.out);
    }
  }
  outputs.commit();

  // The contact sheet is a second output set: without a Vulkan device (or libpng) the models and
  // samples above still stand, and the demo says why the picture is missing.
  const std::string sheet = (std::filesystem::path(a.dir) / "contact_sheet.png").string();
  std::string sheetMissing;
  if (!io::pngSupported()) {
    sheetMissing = "this build has no libpng";
  } else {
    try {
      io::OutputSet picture;
      writeContactSheet(a.dir, picture.add(sheet, "--dir"));
      picture.commit();
      written.push_back(sheet);
    } catch (const render::NoRenderDeviceError& e) {
      sheetMissing = e.what();
    } catch (const vk::VulkanError& e) {
      sheetMissing = std::string("the Vulkan device failed: ") + e.what();
    }
  }

  if (a.quiet) return;
  std::printf("shapespline demo wrote %zu files:\n", written.size());
  for (const auto& w : written) std::printf("  %s\n", w.c_str());
  if (sheetMissing.empty()) {
    std::printf("Look first at %s: %s.\n", sheet.c_str(), kSheetSummary);
  } else {
    std::fprintf(stderr, "shapespline: notice: no %s: %s\n", sheet.c_str(), sheetMissing.c_str());
  }
  std::printf("Then: the .svg plots in a browser, the .obj meshes in any mesh viewer, the .json models with\n"
              "`shapespline render MODEL -o out.png` or `shapespline view MODEL`.\n");
}

}  // namespace

void registerDemo(CLI::App& app) {
  auto a = std::make_shared<DemoArgs>();
  CLI::App* sub = app.add_subcommand("demo", "Write example models, their samples (OBJ, SVG) and a rendered contact sheet (PNG) into ./shapespline-demo/.");
  sub->add_option("--dir", a->dir, "output folder (default ./shapespline-demo)");
  sub->add_option("--device", a->device, "cpu (default), auto or vulkan (as in sample)");
  addQuietFlag(sub, a->quiet, "no list of the files and no notice (the files are written all the same)");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runDemo(*a); });
}

}  // namespace shapespline::cli

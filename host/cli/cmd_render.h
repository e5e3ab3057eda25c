#pragma once
// The `render` command's arguments and its work, also used by `demo` (its contact sheet).
#include <shapespline/cli/common.h>

#include <optional>
#include <string>

namespace shapespline::io {
class OutputSet;
}

namespace shapespline::cli {

struct RenderArgs {
  std::string model, output, size = "800x600", view, sweep;
  std::optional<double> lambda;
  bool wireframe = false, controlNet = false, quiet = false;
  int rate = 16;
  GivenOptions given;  // the options given on the command line (refused where they do not apply)
};

// Reads the model, renders it (one view, or one labelled tile per --sweep value) and writes the PNG
// into `outputs` (added there, with the model as an input); the caller commits.
void renderModel(const RenderArgs& a, io::OutputSet& outputs);

}  // namespace shapespline::cli

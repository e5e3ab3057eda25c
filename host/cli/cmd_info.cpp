// `shapespline info`: Vulkan devices, the one selected, fp64 support and the limits that matter.
#include <shapespline/cli/common.h>
#include <shapespline/io/output_set.h>
#include <shapespline/sampling/devices.h>

namespace shapespline::cli {

void registerInfo(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("info", "Vulkan devices, the selected one, fp64 support and limits.");
  sub->footer(kExitCodeHelp);
  sub->callback([] { io::writeStdout(sampling::describeDevices()); });
}

}  // namespace shapespline::cli

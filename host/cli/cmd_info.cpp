// `shapespline info`: Vulkan devices, the one selected, fp64 support and the limits that matter.
#include <shapespline/cli/common.h>
#include <shapespline/io/output_set.h>
#include <shapespline/sampling/devices.h>

namespace shapespline::cli {

void registerInfo(CLI::App& app) {
  CLI::App* sub = app.add_subcommand("info", "Vulkan devices, the selected one, fp64 support and limits.");
  auto quiet = std::make_shared<bool>(false);
  addQuietFlag(sub, *quiet, "accepted for uniformity: the description is info's output");
  sub->footer(kExitCodeHelp);
  sub->callback([quiet] { io::writeStdout(sampling::describeDevices()); });  // `quiet` lives with the callback
}

}  // namespace shapespline::cli

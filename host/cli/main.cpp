// shapespline: the command line. main catches everything and maps it to the documented exit codes:
// 0 success, 2 bad input (ModelError, InputError, OutputPathError, argument errors), 3 device or
// runtime error (RuntimeError, VulkanError, OutputWriteError, internal errors).
#include "cli/common.h"
#include "cli/exit_codes.h"
#include "core/model.h"
#include "io/atomic_file.h"

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <exception>
#include <new>

namespace {

int report(const std::string& field, const std::string& reason, int code) {
  std::fprintf(stderr, "shapespline: error: %s: %s\n", field.c_str(), reason.c_str());
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shapespline;
  using namespace shapespline::cli;
  // A file size limit (ulimit -f) would otherwise kill the process mid-write and leave the
  // temporary file behind; ignored, the write fails with EFBIG and is reported (exit 3).
  std::signal(SIGXFSZ, SIG_IGN);
  takeCliFault();
  CLI::App app{"shapespline: evaluate and sample shape-parametric spline curves and surfaces "
               "(CPU fp64 or Vulkan compute)."};
  app.footer(std::string(kExitCodeHelp) +
             "\nRun 'shapespline demo' for example models and outputs in ./shapespline-demo/.");
  app.require_subcommand(1);
  registerSample(app);
  registerEval(app);
  registerBasis(app);
  registerGbFit(app);
  registerExtend(app);
  registerInfo(app);
  registerDemo(app);
  registerMerge(app);
  registerRender(app);

  try {
    app.parse(argc, argv);
    return kExitSuccess;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints CLI11's message and a usage hint
    return kExitBadInput;
  } catch (const ModelError& e) {
    return report(e.field(), e.rule() + (e.value().empty() ? "" : " (got " + e.value() + ")"), kExitBadInput);
  } catch (const InputError& e) {
    return report(e.field(), e.rule() + (e.value().empty() ? "" : " (got " + e.value() + ")"), kExitBadInput);
  } catch (const io::OutputPathError& e) {
    return report(e.option(), "'" + e.path() + "': " + e.reason(), kExitBadInput);
  } catch (const io::OutputWriteError& e) {
    return report(e.option(), "cannot write '" + e.path() + "': " + e.reason(), kExitRuntime);
  } catch (const RuntimeError& e) {
    return report(e.field(), e.rule() + (e.value().empty() ? "" : " (got " + e.value() + ")"), kExitRuntime);
  } catch (const std::invalid_argument& e) {
    return report("input", e.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return report("memory", "out of memory", kExitRuntime);
  } catch (const std::exception& e) {
    return report("runtime", e.what(), kExitRuntime);
  } catch (...) {
    return report("runtime", "unknown error", kExitRuntime);
  }
}

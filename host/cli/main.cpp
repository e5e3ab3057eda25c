// shapespline: the command line. main catches everything and maps it to the documented exit codes:
// 0 success, 2 bad input (ModelError, InputError, jobs::JobInputError, OutputPathError, argument errors), 3 device or
// runtime error (RuntimeError, sampling::DeviceError, OutputWriteError, internal errors).
#include <shapespline/cli/common.h>
#include <shapespline/cli/exit_codes.h>
#include <shapespline/core/model.h>
#include <shapespline/io/atomic_file.h>
#include <shapespline/io/input_file.h>
#include <shapespline/io/output_set.h>
#include <shapespline/jobs/job_input_error.h>
#include <shapespline/sampling/report.h>
#include <shapespline/version.h>

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

// CLI11's message split into the option it names and the reason, in the error format of every other
// failure. CLI11 2.x keeps no option name in its errors, so the name is read from the message forms
// it writes: "Could not convert: NAME = VALUE", "NAME: REASON", "NAME is required". Anything else
// (extra arguments, a missing subcommand) is about the arguments as a whole.
int reportParseError(const CLI::ParseError& e) {
  constexpr size_t kMaxMessageChars = 200;  // the message quotes the argument: keep it bounded
  const std::string msg = e.what();
  std::string field = "arguments", reason = msg;
  const auto isName = [](const std::string& s) {
    return !s.empty() && s.find(' ') == std::string::npos && s.size() <= 64;
  };
  if (const std::string conv = "Could not convert: "; msg.rfind(conv, 0) == 0) {
    const size_t eq = msg.find(" = ", conv.size());
    if (eq != std::string::npos && isName(msg.substr(conv.size(), eq - conv.size()))) {
      field = msg.substr(conv.size(), eq - conv.size());
      reason = "could not convert the value to the option's type (got " + msg.substr(eq + 3) + ")";
    }
  } else if (const size_t colon = msg.find(": "); colon != std::string::npos && isName(msg.substr(0, colon))) {
    field = msg.substr(0, colon);
    reason = msg.substr(colon + 2);
  } else if (const std::string req = " is required"; msg.size() > req.size() &&
                                                      msg.compare(msg.size() - req.size(), req.size(), req) == 0 &&
                                                      isName(msg.substr(0, msg.size() - req.size()))) {
    field = msg.substr(0, msg.size() - req.size());
    reason = "required, but not given";
  }
  report(field, shapespline::io::shortText(reason, kMaxMessageChars), shapespline::cli::kExitBadInput);
  std::fprintf(stderr, "Run with --help for more information.\n");
  return shapespline::cli::kExitBadInput;
}

// "<rule> (got <value>)" with the value cut to a bounded length: values can come from argv (up to
// 128 KiB each) and must not flood the terminal or a log.
template <class E>
std::string ruleAndValue(const E& e) {
  constexpr size_t kMaxShownValueChars = 200;
  if (e.value().empty()) return e.rule();
  return e.rule() + " (got " + shapespline::io::shortText(e.value(), kMaxShownValueChars) + ")";
}

}  // namespace

int main(int argc, char** argv) {
  using namespace shapespline;
  using namespace shapespline::cli;
  // A file size limit (ulimit -f) would otherwise kill the process mid-write and leave the
  // temporary file behind; ignored, the write fails with EFBIG and is reported (exit 3).
  std::signal(SIGXFSZ, SIG_IGN);
  // SIGINT/SIGTERM/SIGHUP remove the temporary output files, then end the process by the signal.
  io::installTempFileCleanup();
  takeCliFault();
  CLI::App app{"shapespline: evaluate and sample shape-parametric spline curves and surfaces "
               "(CPU fp64 or Vulkan compute)."};
  app.footer(std::string(kExitCodeHelp) +
             "\nRun 'shapespline demo' for example models and outputs in ./shapespline-demo/.");
  // One line: the version of project(VERSION) and the commit the binary was configured from.
  app.set_version_flag("--version", "shapespline " SHAPESPLINE_VERSION_STRING " (commit " SHAPESPLINE_GIT_COMMIT ")",
                       "Print the version and the git commit, then exit");
  app.require_subcommand(1);
  registerSample(app);
  registerEval(app);
  registerBasis(app);
  registerGbFit(app);
  registerExtend(app);
  registerImport(app);
  registerInfo(app);
  registerDemo(app);
  registerMerge(app);
  registerRender(app);
  registerView(app);
  registerProject(app);

  try {
    app.parse(argc, argv);
    io::flushStdout();  // a full disk or a closed stream behind stdout is a failed output (exit 3)
    return kExitSuccess;
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return reportParseError(e);  // "shapespline: error: <option>: <reason>" and a usage hint
  } catch (const BatchFailure& e) {
    return report("MODEL", e.what(), kExitSomeFailed);
  } catch (const ModelError& e) {
    return report(e.field(), ruleAndValue(e), kExitBadInput);
  } catch (const InputError& e) {
    return report(e.field(), ruleAndValue(e), kExitBadInput);
  } catch (const jobs::JobInputError& e) {
    return report(e.field(), ruleAndValue(e), kExitBadInput);
  } catch (const io::OutputPathError& e) {
    return report(e.option(), "'" + e.path() + "': " + e.reason(), kExitBadInput);
  } catch (const io::OutputWriteError& e) {
    // A stream (stdout) has no path: "stdout: write failed: ...".
    return report(e.option(), e.path().empty() ? e.reason() : "cannot write '" + e.path() + "': " + e.reason(),
                  kExitRuntime);
  } catch (const RuntimeError& e) {
    return report(e.field(), ruleAndValue(e), kExitRuntime);
  } catch (const sampling::DeviceError& e) {
    return report(e.fallbackRefused() ? "--require-device" : "vulkan", std::string(e.what()) + " (no output written)",
                  kExitRuntime);
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

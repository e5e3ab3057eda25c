// libFuzzer target over `merge` (jobs/merge.h, issue 12): the input becomes 1-3 shard files in a
// private temporary folder and jobs::mergeShards joins them.
//
// Input layout (merge_fuzz_format.h): byte 0 chooses the format (obj, ply, csv, f64, f32); the rest
// is split at kMergeFuzzSeparator into parts: one file per shard, or for raw formats pairs of data
// file and sidecar (a missing sidecar stays missing). The contract checked here:
//  * mergeShards returns or throws MergeError / MergeReadError; nothing else escapes (a crash, a
//    sanitizer report, a leak or a hang is a finding, as any other exception);
//  * on failure no output and no temporary file is left in the folder;
//  * on success the output exists, and merging it again as the single shard 1/1 reproduces it
//    byte for byte (raw: the data, and the sidecar but for its data_file name);
//  * the folder and everything in it is removed afterwards.
// The same function is linked into `merge_fuzz_replay` (replay_main.cpp) for builds without libFuzzer.
#include "merge_fuzz_format.h"

#include <shapespline/io/atomic_file.h>
#include <shapespline/jobs/merge.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

namespace {

namespace fs = std::filesystem;
using namespace shapespline;

constexpr size_t kMaxInputBytes = 1 << 16;

[[noreturn]] void finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "merge_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

void writeFile(const fs::path& p, std::string_view bytes) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) finding("cannot write the fuzz input", p.string());
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::set<std::string> entries(const fs::path& dir) {
  std::set<std::string> s;
  for (const auto& e : fs::directory_iterator(dir)) s.insert(e.path().filename().string());
  return s;
}

// Runs the merge; true on success, false on a refusal the contract allows.
bool merge(const std::vector<std::string>& shards, const std::string& out) {
  try {
    jobs::mergeShards(shards, out);
    return true;
  } catch (const jobs::MergeError&) {
  } catch (const jobs::MergeReadError&) {
  } catch (const io::OutputWriteError&) {  // a full /tmp
  } catch (const std::exception& e) {
    finding("unexpected exception", e.what());
  }
  return false;
}

// Removes the folder whatever happens in between.
struct TempDir {
  fs::path path;
  TempDir() {
    // A RAM file system when there is one: every successful merge fsyncs its output (io/output_set.h),
    // which on a disk would dominate the run time.
    const char* env = std::getenv("TMPDIR");
    const fs::path base = env && *env ? fs::path(env) : fs::is_directory("/dev/shm") ? fs::path("/dev/shm")
                                                                                        : fs::temp_directory_path();
    std::string t = (base / "merge_fuzz_XXXXXX").string();
    if (!::mkdtemp(t.data())) finding("mkdtemp", t);
    path = t;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void check(const shapespline::test::MergeFuzzInput& in) {
  TempDir dir;
  const std::string ext = in.extension();
  std::vector<std::string> shards;
  std::set<std::string> inputs;
  for (size_t k = 0; k < in.shards.size(); ++k) {
    std::string name(1, 's');  // (not "s" + std::string: GCC 12 warns falsely, -Wrestrict)
    name += std::to_string(k + 1) + "." + ext;
    writeFile(dir.path / name, in.shards[k].data);
    inputs.insert(name);
    if (in.shards[k].hasSidecar) {
      writeFile(dir.path / (name + ".json"), in.shards[k].sidecar);
      inputs.insert(name + ".json");
    }
    shards.push_back((dir.path / name).string());
  }
  const std::string out = (dir.path / ("out." + ext)).string();
  if (!merge(shards, out)) {
    if (entries(dir.path) != inputs) finding("a refused merge left files behind", ext);
    return;
  }
  if (!fs::exists(out) || (in.raw() && !fs::exists(out + ".json"))) finding("merge succeeded without output", ext);
  // The merged file is the unsharded job's: on its own it is shard 1/1 and merges to itself.
  const std::string again = (dir.path / ("again." + ext)).string();
  if (!merge({out}, again)) finding("the merged file does not merge as shard 1/1", ext);
  if (readFile(again) != readFile(out)) finding("merging the merged file changed it", ext);
  if (in.raw()) {
    std::string a = readFile(again + ".json"), b = readFile(out + ".json");
    const std::string from = "\"data_file\": \"again." + ext + "\"", to = "\"data_file\": \"out." + ext + "\"";
    const size_t at = a.find(from);
    if (at == std::string::npos) finding("merged sidecar without its data_file", a.substr(0, 200));
    a.replace(at, from.size(), to);
    if (a != b) finding("merging the merged file changed its sidecar", ext);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0 || size > kMaxInputBytes) return 0;
  check(shapespline::test::decodeMergeFuzzInput(std::string_view(reinterpret_cast<const char*>(data), size)));
  return 0;
}

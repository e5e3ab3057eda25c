// `shapespline merge -o OUT SHARD...`: joins the outputs of `sample --shard K/N` or `project --shard K/N` (given in shard
// order) into the file the unsharded job writes, byte for byte, after verifying that they are the
// shards 1..N of one job (jobs/merge.h, which does the work; this file only maps its errors).
#include <shapespline/cli/common.h>
#include <shapespline/jobs/shard_files.h>
#include <shapespline/jobs/merge.h>

#include <memory>

namespace shapespline::cli {
namespace {

struct MergeArgs {
  std::string out;
  std::vector<std::string> inputs;
  bool quiet = false;
};

void runMerge(const MergeArgs& a) {
  try {
    // A shard pattern expanded, shard records verified (jobs/shard_files.h), then the merge itself.
    jobs::mergeShards(jobs::mergeInputs(a.inputs), a.out);
  } catch (const jobs::MergeError& e) {
    throw InputError(e.field(), e.value(), e.rule());
  } catch (const jobs::MergeReadError& e) {
    throw RuntimeError(e.field(), e.value(), e.rule());
  }
}

}  // namespace

void registerMerge(CLI::App& app) {
  auto a = std::make_shared<MergeArgs>();
  CLI::App* sub = app.add_subcommand(
      "merge", "Join `sample --shard K/N` or `project --shard K/N` outputs (shards 1..N of one job, in order) into the unsharded job's file.");
  sub->add_option("SHARD", a->inputs,
                  "shard files, K = 1..N in order (errors name them SHARD[K]), or one shard pattern such as "
                  "'out-{shard:05d}-of-{count:05d}.f32' (expanded to the shards 1..N present); a shard's record "
                  "SHARD.shard.json, where present, is verified first")
      ->required();
  sub->add_option("-o,--output", a->out, "merged file (.obj .ply .csv .f32 .f64 .npy)")->required();
  addQuietFlag(sub, a->quiet, "accepted for uniformity: merge prints only errors");
  sub->footer(kExitCodeHelp);
  sub->callback([a] { runMerge(*a); });
}

}  // namespace shapespline::cli

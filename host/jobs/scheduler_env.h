#pragma once
// `sample --shard auto`: the shard K of N from the scheduler's environment (issue 16, requirement 2).
//  * Slurm job arrays (sbatch --array=A-B): K = SLURM_ARRAY_TASK_ID - MIN + 1, N = MAX - MIN + 1
//    from SLURM_ARRAY_TASK_MIN / _MAX; one of them may be missing when SLURM_ARRAY_TASK_COUNT gives
//    it (MIN = MAX - COUNT + 1, MAX = MIN + COUNT - 1); COUNT, when set, must equal MAX - MIN + 1
//    (a list such as --array=1,3,7 has gaps), and SLURM_ARRAY_TASK_STEP, when set, must be 1.
//  * Kubernetes Indexed Jobs (completionMode: Indexed): K = JOB_COMPLETION_INDEX + 1 (0-based), N
//    from --shard-count N or, without it, SHAPESPLINE_SHARD_COUNT (both given: they must agree).
// --shard-count or SHAPESPLINE_SHARD_COUNT beside a Slurm array must agree with its N. Every
// refusal is an InputError (exit 2) naming the variable, its value and the rule; neither scheduler
// in the environment, or both, is one too (naming --shard).
#include <functional>
#include <string>

namespace shapespline::jobs {

struct ShardChoice {
  int index = 1, count = 1;  // K of N
  std::string source;        // "" (--shard K/N or none), "Slurm job array", "Kubernetes Indexed Job"
};

// Looks up an environment variable: nullptr when unset (std::getenv's contract).
using EnvLookup = std::function<const char*(const char*)>;

// `shardCount` is --shard-count as given ("" = not given).
ShardChoice shardFromEnvironment(const EnvLookup& env, const std::string& shardCount);

// --shard as given: "" (1/1), "K/N", or "auto" (shardFromEnvironment with the process environment).
// --shard-count is refused unless --shard is auto.
ShardChoice parseShardOption(const std::string& shard, const std::string& shardCount);

}  // namespace shapespline::jobs

#include <shapespline/jobs/scheduler_env.h>

#include <shapespline/io/shard_info.h>
#include <shapespline/jobs/job_input_error.h>

#include <cstdint>
#include <cstdlib>
#include <optional>

namespace shapespline::jobs {
namespace {

constexpr size_t kMaxDigits = 10;

const char* const kId = "SLURM_ARRAY_TASK_ID";
const char* const kMin = "SLURM_ARRAY_TASK_MIN";
const char* const kMax = "SLURM_ARRAY_TASK_MAX";
const char* const kCount = "SLURM_ARRAY_TASK_COUNT";
const char* const kStep = "SLURM_ARRAY_TASK_STEP";
const char* const kK8sIndex = "JOB_COMPLETION_INDEX";
const char* const kCountVar = "SHAPESPLINE_SHARD_COUNT";

// A non-negative decimal integer of at most 10 digits (no sign, no spaces), as schedulers write them.
uint64_t parseNumber(const std::string& text, const std::string& field) {
  if (text.empty() || text.size() > kMaxDigits || text.find_first_not_of("0123456789") != std::string::npos) {
    throw JobInputError(field, text.empty() ? "(empty)" : text,
                     "must be a non-negative decimal integer of at most 10 digits");
  }
  return std::strtoull(text.c_str(), nullptr, 10);
}

std::optional<uint64_t> number(const EnvLookup& env, const char* name) {
  const char* v = env(name);
  if (!v) return std::nullopt;
  return parseNumber(v, name);
}

uint64_t parseCount(const std::string& text, const std::string& field) {
  const uint64_t n = parseNumber(text, field);
  if (n < 1 || n > io::kMaxShardCount) throw JobInputError(field, text, "the shard count must be in [1, 1000000000]");
  return n;
}

// --shard-count, else SHAPESPLINE_SHARD_COUNT; both given must agree. nullopt when neither.
std::optional<uint64_t> givenCount(const EnvLookup& env, const std::string& option) {
  std::optional<uint64_t> fromOption, fromEnv;
  if (!option.empty()) fromOption = parseCount(option, "--shard-count");
  if (const char* v = env(kCountVar)) fromEnv = parseCount(v, kCountVar);
  if (fromOption && fromEnv && *fromOption != *fromEnv) {
    throw JobInputError(kCountVar, std::to_string(*fromEnv),
                     "differs from --shard-count " + std::to_string(*fromOption) + "; give one shard count");
  }
  return fromOption ? fromOption : fromEnv;
}

ShardChoice fromSlurm(const EnvLookup& env, const std::string& shardCountOption) {
  const std::optional<uint64_t> id = number(env, kId), lo = number(env, kMin), hi = number(env, kMax),
                                count = number(env, kCount), step = number(env, kStep);
  if (!id) {
    throw JobInputError(kId, "(not set)",
                     "is needed beside SLURM_ARRAY_TASK_MIN/MAX/COUNT: --shard auto reads the task of a Slurm job "
                     "array (sbatch --array=1-N)");
  }
  if (step && *step != 1) {
    throw JobInputError(kStep, std::to_string(*step),
                     "must be 1: a job array with a step (--array=A-B:S) leaves gaps between its task ids, and "
                     "--shard auto numbers the shards by consecutive ids; use --array=A-B, or --shard K/N");
  }
  if (count && *count < 1) throw JobInputError(kCount, "0", "must be at least 1");
  uint64_t first = 0, last = 0;
  if (lo) {
    first = *lo;
  } else if (hi && count) {
    if (*count > *hi + 1) {
      throw JobInputError(kCount, std::to_string(*count),
                       "exceeds SLURM_ARRAY_TASK_MAX + 1 = " + std::to_string(*hi + 1) +
                           " (the first task id would be negative)");
    }
    first = *hi - *count + 1;
  } else {
    throw JobInputError(kMin, "(not set)",
                     "is needed (or SLURM_ARRAY_TASK_MAX and SLURM_ARRAY_TASK_COUNT) to number the shards: "
                     "K = SLURM_ARRAY_TASK_ID - SLURM_ARRAY_TASK_MIN + 1");
  }
  if (hi) {
    last = *hi;
  } else if (count) {
    last = first + *count - 1;
  } else {
    throw JobInputError(kMax, "(not set)",
                     "is needed (or SLURM_ARRAY_TASK_COUNT) for the shard count: N = SLURM_ARRAY_TASK_MAX - "
                     "SLURM_ARRAY_TASK_MIN + 1");
  }
  if (first > last) {
    throw JobInputError(kMin, std::to_string(first),
                     "must not exceed SLURM_ARRAY_TASK_MAX (" + std::to_string(last) + ")");
  }
  const uint64_t n = last - first + 1;
  if (count && *count != n) {
    throw JobInputError(kCount, std::to_string(*count),
                     "must equal SLURM_ARRAY_TASK_MAX - SLURM_ARRAY_TASK_MIN + 1 = " + std::to_string(n) +
                         ": the array's task ids are not consecutive (a list such as --array=1,3,7); --shard auto "
                         "needs --array=A-B");
  }
  if (*id < first || *id > last) {
    throw JobInputError(kId, std::to_string(*id),
                     "must lie in [SLURM_ARRAY_TASK_MIN, SLURM_ARRAY_TASK_MAX] = [" + std::to_string(first) + ", " +
                         std::to_string(last) + "]");
  }
  if (n > io::kMaxShardCount) {
    throw JobInputError(kMax, std::to_string(last),
                     "gives " + std::to_string(n) + " shards (MAX - MIN + 1); at most 1000000000 are allowed");
  }
  if (const std::optional<uint64_t> given = givenCount(env, shardCountOption); given && *given != n) {
    const bool option = !shardCountOption.empty();
    throw JobInputError(option ? "--shard-count" : kCountVar, std::to_string(*given),
                     "differs from the Slurm job array's task count " + std::to_string(n) +
                         " (SLURM_ARRAY_TASK_MAX - SLURM_ARRAY_TASK_MIN + 1)");
  }
  return {static_cast<int>(*id - first + 1), static_cast<int>(n), "Slurm job array"};
}

ShardChoice fromKubernetes(const EnvLookup& env, const std::string& shardCountOption) {
  const uint64_t index = *number(env, kK8sIndex);
  const std::optional<uint64_t> n = givenCount(env, shardCountOption);
  if (!n) {
    throw JobInputError("--shard-count", "(not given)",
                     "--shard auto in a Kubernetes Indexed Job (JOB_COMPLETION_INDEX is set) needs the job's "
                     "completions as --shard-count N or SHAPESPLINE_SHARD_COUNT");
  }
  if (index >= *n) {
    throw JobInputError(kK8sIndex, std::to_string(index),
                     "must be below the shard count " + std::to_string(*n) +
                         " (the index is 0-based: 0 .. completions - 1)");
  }
  return {static_cast<int>(index + 1), static_cast<int>(*n), "Kubernetes Indexed Job"};
}

}  // namespace

ShardChoice shardFromEnvironment(const EnvLookup& env, const std::string& shardCount) {
  const bool slurm = env(kId) || env(kMin) || env(kMax) || env(kCount) || env(kStep);
  const bool k8s = env(kK8sIndex) != nullptr;
  if (slurm && k8s) {
    throw JobInputError("--shard", "auto",
                     "both a Slurm job array (SLURM_ARRAY_TASK_*) and a Kubernetes Indexed Job "
                     "(JOB_COMPLETION_INDEX) are in the environment; unset one, or give --shard K/N");
  }
  if (slurm) return fromSlurm(env, shardCount);
  if (k8s) return fromKubernetes(env, shardCount);
  throw JobInputError("--shard", "auto",
                   "no scheduler task index in the environment: SLURM_ARRAY_TASK_ID (a Slurm job array, sbatch "
                   "--array=1-N) or JOB_COMPLETION_INDEX (a Kubernetes Indexed Job) must be set; or give --shard K/N");
}

ShardChoice parseShardOption(const std::string& text, const std::string& shardCount) {
  if (text == "auto") return shardFromEnvironment([](const char* name) { return std::getenv(name); }, shardCount);
  if (!shardCount.empty()) {
    throw JobInputError("--shard-count", shardCount,
                     "is for --shard auto (a Kubernetes Indexed Job's completions); --shard K/N gives N itself");
  }
  if (text.empty()) return {1, 1, ""};
  const size_t slash = text.find('/');
  const std::string rule = "expected K/N with 1 <= K <= N <= 1000000000, or auto";
  if (slash == std::string::npos) throw JobInputError("--shard", text, rule);
  char* e1 = nullptr;
  char* e2 = nullptr;
  const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
  const long long k = std::strtoll(a.c_str(), &e1, 10), n = std::strtoll(b.c_str(), &e2, 10);
  if (a.empty() || b.empty() || *e1 || *e2 || n < 1 || k < 1 || k > n || static_cast<uint64_t>(n) > io::kMaxShardCount) {
    throw JobInputError("--shard", text, rule);
  }
  return {static_cast<int>(k), static_cast<int>(n), ""};
}

}  // namespace shapespline::jobs

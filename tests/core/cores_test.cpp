// availableCores (core/cores.h) counts the CPUs of the calling thread's affinity mask, so a job
// pinned to fewer CPUs (a Slurm task, taskset) starts that many workers, not one per CPU of the node.
#include <gtest/gtest.h>

#include <sched.h>

#include <thread>

#include <shapespline/core/cores.h>

namespace shapespline {
namespace {

TEST(AvailableCores, FollowsTheAffinityMask) {
  cpu_set_t all;
  CPU_ZERO(&all);
  ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
  EXPECT_EQ(availableCores(), CPU_COUNT(&all));
  // A thread pinned to one of those CPUs sees one (affinity is per thread: the test's own mask
  // stays as it was).
  int cpu = 0;
  while (!CPU_ISSET(cpu, &all)) ++cpu;
  int seen = 0;
  std::thread pinned([&] {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    if (sched_setaffinity(0, sizeof one, &one) == 0) seen = availableCores();
  });
  pinned.join();
  EXPECT_EQ(seen, 1);
  EXPECT_EQ(availableCores(), CPU_COUNT(&all));
}

}  // namespace
}  // namespace shapespline

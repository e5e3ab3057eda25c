#pragma once
// How many threads of work the process should run by default.
namespace shapespline {

// The CPUs the calling thread may run on: its affinity mask (a Slurm task's CPUs under the
// task/affinity or task/cgroup plugins, a cgroup cpuset, `taskset`), not the machine's hardware
// threads, which a job given 8 CPUs of a 64-core node would oversubscribe 8-fold. At least 1.
int availableCores();

}  // namespace shapespline

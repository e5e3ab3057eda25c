# Sourced by scripts/test.sh and scripts/sanitize.sh: the gtest executables and which of their tests
# run in which build.
#
# The gtest executables (tests/CMakeLists.txt, shapespline_test_dir), longest first.
gtest_executables=(cli_tests gpu_tests io_tests core_tests sampling_tests cad_tests jobs_tests)
# Tests that measure peak RSS, which ASan's quarantine and shadow memory inflate by hundreds of MiB:
# they run in the Release build only (a gtest filter).
release_only_gtests="GpuStreamLarge.JobStreamsInBoundedMemory:MemoryBoundRss.*"

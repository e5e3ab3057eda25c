# Sourced by scripts/test.sh and scripts/sanitize.sh: which gtest executables run in which build.
#
# Under the sanitizers (build-asan), longest process first (gpu_tests runs as one process, cli_tests
# as several: scripts/sanitize.sh): every gtest but the peak-RSS ones.
sanitized_gtests=(gpu_tests cli_tests part_tests io_tests core_tests sampling_tests cad_tests jobs_tests)
# In the Release build: the peak-RSS tests (tests/memory; ASan's shadow memory and quarantine would
# inflate them by hundreds of MiB), and the golden vectors against the -O3 library people install.
release_gtests=(memory_tests core_tests)

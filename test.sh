#!/usr/bin/env bash
# Command 2 of the README: the whole test suite — Release build, then a Debug build with
# AddressSanitizer + UndefinedBehaviorSanitizer — every CTest test in both.
set -euo pipefail
cd "$(dirname "$0")"
tools/deps.sh
jobs="$(nproc)"

echo "== Release build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
# A fresh tree has no run times for CTest to schedule by, and runs the tests in declaration order:
# the long Blender and POV-Ray tests then come last and leave a core idle at the end. The
# checked-in times (tests/ctest_costs.txt, refreshed by tools/update_test_costs.sh) let it start
# the longest first; a tree that has run its tests keeps its own.
seed_test_costs() {
  mkdir -p "$1/Testing/Temporary"
  [ -f "$1/Testing/Temporary/CTestCostData.txt" ] ||
    cp tests/ctest_costs.txt "$1/Testing/Temporary/CTestCostData.txt"
}
seed_test_costs build
ctest --test-dir build --output-on-failure -j"$jobs"

# (POV-Ray itself is not built under the sanitizers: povray-facet and its `povray` tests run in
# the Release tree above; the bridge's logic is the core's, which the ASan tree tests.)
echo "== Debug + ASan/UBSan build and tests"
# The libFuzzer sub-build (clang, ASan+UBSan already) and its time-limited runs are the Release
# tree's; this tree still replays the fuzz corpora under GCC's sanitizers (*_fuzz_replay).
# The Python module is tested in the Release tree only: under ASan it would need libasan
# preloaded into /usr/bin/python3 (and leak checks off for the interpreter).
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DFACET_SANITIZE=ON -DFACET_BUILD_BENCH=OFF \
  -DFACET_BUILD_PYTHON=OFF -DFACET_BUILD_POVRAY=OFF -DFACET_BUILD_BLENDER=OFF -DFACET_FUZZ=OFF
cmake --build build-asan -j"$jobs"
seed_test_costs build-asan
# Stress and convergence tests scale their query counts down under sanitizers (see tests/).
FACET_STRESS_SCALE=0.1 ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j"$jobs"

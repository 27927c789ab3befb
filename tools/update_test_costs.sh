#!/usr/bin/env bash
# Refreshes tests/ctest_costs.txt, the test run times test.sh seeds a fresh tree with so that
# CTest starts the longest tests first: the Release tree's and the ASan tree's own CTest cost
# data (Testing/Temporary/CTestCostData.txt, written by every ctest run) merged, the larger time
# kept for a test in both. Run after ./test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
out=tests/ctest_costs.txt
cat build/Testing/Temporary/CTestCostData.txt build-asan/Testing/Temporary/CTestCostData.txt 2>/dev/null |
  awk '/^---/{skip=1} !skip && NF==3 {if (!($1 in c) || $3 > c[$1]) {c[$1]=$3; n[$1]=1}}
       END {for (t in c) printf "%s %d %.4f\n", t, n[t], c[t]}' | LC_ALL=C sort > "$out.tmp"
echo "---" >> "$out.tmp"
mv "$out.tmp" "$out"
echo "update_test_costs: $(grep -c . "$out") lines in $out"

# Runs the libFuzzer scene-loader fuzzer from the corpus for SECONDS seconds. New inputs go to
# WORK/new (never into the source corpus); a crash input is written to WORK/artifacts/ and fails
# the test. A fixed seed makes a CI failure reproducible (the run is still time-limited, so how
# far it gets varies); explore with other seeds by hand and add what they find to the corpus. Invoked by CTest (tests/render/fuzz/CMakeLists.txt).
if(NOT EXISTS "${FUZZER}")
  message(FATAL_ERROR "fuzzer binary not built: ${FUZZER} (build target facet_fuzz_clang)")
endif()
file(MAKE_DIRECTORY "${WORK}/new" "${WORK}/artifacts")
execute_process(
  COMMAND "${FUZZER}" -seed=1 -max_total_time=${SECONDS} -timeout=10 -rss_limit_mb=2560
          -dict=${DICT} -artifact_prefix=${WORK}/artifacts/ -print_final_stats=1
          "${WORK}/new" "${CORPUS}"
  RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the scene-loader fuzzer failed (exit ${rc}); see ${WORK}/artifacts")
endif()

# run_fuzzer.cmake — one short fuzzing run for CTest (see CMakeLists.txt here).
#
# First runs FUZZER once on each seed in CORPUS, so a seed that crashes (a regression
# input) is named; then copies the seeds to WORK/corpus (libFuzzer adds the inputs it finds
# to its first corpus folder, and the source tree must stay clean) and fuzzes for at most
# SECONDS seconds or RUNS inputs, failing with the reproducer's location on a crash. Work
# files go under WORK/tmp, so a crashed run leaves nothing in /tmp.
# Inputs: FUZZER, CORPUS, WORK, SECONDS, RUNS, optional DICT.
file(REMOVE_RECURSE ${WORK})
file(MAKE_DIRECTORY ${WORK}/corpus ${WORK}/artifacts ${WORK}/tmp)
set(env ${CMAKE_COMMAND} -E env TMPDIR=${WORK}/tmp)

file(GLOB seeds ${CORPUS}/*)
execute_process(COMMAND ${env} ${FUZZER} ${seeds} RESULT_VARIABLE rc OUTPUT_VARIABLE log
                ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  string(REGEX MATCHALL "Running: [^\n]*" running "${log}")
  list(POP_BACK running last)
  message("${log}")
  message(FATAL_ERROR "${FUZZER} crashes on a seed (exit ${rc}): ${last}")
endif()

file(COPY ${CORPUS}/ DESTINATION ${WORK}/corpus)
set(args -max_total_time=${SECONDS} -runs=${RUNS} -print_final_stats=1
         -artifact_prefix=${WORK}/artifacts/)
if(DICT)
  list(APPEND args -dict=${DICT})
endif()
execute_process(COMMAND ${env} ${FUZZER} ${args} ${WORK}/corpus RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  file(GLOB found ${WORK}/artifacts/*)
  message(FATAL_ERROR "${FUZZER} failed (exit ${rc}); reproducer: ${found}")
endif()

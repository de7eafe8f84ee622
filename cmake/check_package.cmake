# ctest script: install npend into a scratch prefix, then configure, build and run
# tests/package_consumer against it. Variables: BUILD_DIR, SOURCE_DIR, WORK_DIR, and
# CONSUMER_FLAGS (compiler flags the consumer needs, e.g. the sanitizers of a sanitized build);
# with PYTHON and PYTHON_DIR (the package's directory under the prefix) also imports the
# installed Python package and integrates a chain with it.
file(REMOVE_RECURSE "${WORK_DIR}")
foreach(step
    "${CMAKE_COMMAND};--install;${BUILD_DIR};--prefix;${WORK_DIR}/prefix"
    "${CMAKE_COMMAND};-S;${SOURCE_DIR}/tests/package_consumer;-B;${WORK_DIR}/build;-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix;-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}"
    "${CMAKE_COMMAND};--build;${WORK_DIR}/build"
    "${WORK_DIR}/build/consumer")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "step failed (${rc}): ${step}\n${out}\n${err}")
  endif()
endforeach()
message(STATUS "package consumer: ${out}")
if(PYTHON)
  set(site "${WORK_DIR}/prefix/${PYTHON_DIR}")
  set(check "import npend, os; assert os.path.realpath(npend.__file__).startswith(os.path.realpath('${site}')), npend.__file__; t, X = npend.simulate(npend.Chain(2), [1, 0, 0, 0], 1.0); print('python package:', npend.__file__, X.shape)")
  execute_process(COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${site}" PYTHONDONTWRITEBYTECODE=1
                          "${PYTHON}" -c "${check}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the installed Python package does not work (${rc}):\n${out}\n${err}")
  endif()
  message(STATUS "${out}")
endif()

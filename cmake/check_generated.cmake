# ctest script: fails when the committed generated/ differs from fresh generator output
# (MODE=drift), or when two generator runs differ byte for byte (MODE=determinism).
# Variables: GEN (npend-gen), SOURCE_DIR, WORK_DIR, LINKS and MODELS (comma-separated), MODE.

function(run_generator out_dir links)
  file(REMOVE_RECURSE "${out_dir}")
  execute_process(
    COMMAND "${GEN}" --index ${LINKS} --loop --out "${out_dir}"
    RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "npend-gen --index failed (${rc}): ${err}")
  endif()
  string(REPLACE "," ";" models "${MODELS}")
  foreach(model IN LISTS models)
    execute_process(
      COMMAND "${GEN}" --links ${links} --model ${model} --out "${out_dir}"
      RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "npend-gen --model ${model} failed (${rc}): ${err}")
    endif()
  endforeach()
endfunction()

function(compare_dirs a b hint)
  file(GLOB files_a RELATIVE "${a}" "${a}/*.hpp" "${a}/*.cpp" "${a}/*.cuh")
  file(GLOB files_b RELATIVE "${b}" "${b}/*.hpp" "${b}/*.cpp" "${b}/*.cuh")
  list(SORT files_a)
  list(SORT files_b)
  if(NOT files_a STREQUAL files_b)
    message(FATAL_ERROR "File sets differ:\n  ${a}: ${files_a}\n  ${b}: ${files_b}\n${hint}")
  endif()
  set(bad)
  foreach(f IN LISTS files_a)
    file(READ "${a}/${f}" ca)
    file(READ "${b}/${f}" cb)
    if(NOT ca STREQUAL cb)
      list(APPEND bad "${f}")
    endif()
  endforeach()
  if(bad)
    message(FATAL_ERROR "These files differ: ${bad}\n${hint}")
  endif()
endfunction()

string(REPLACE "," ";" link_list "${LINKS}")
if(MODE STREQUAL "drift")
  run_generator("${WORK_DIR}/fresh" "${LINKS}")
  compare_dirs("${WORK_DIR}/fresh" "${SOURCE_DIR}/generated"
    "generated/ is out of date with the generator. Maybe you forgot to run the generator "
    "after changing it? Run: cmake --build <build> --target npend_regenerate, and commit generated/.")
  message(STATUS "generated/ matches the generator for link counts ${LINKS}")
elseif(MODE STREQUAL "determinism")
  # Two processes (different addresses, so different GiNaC hash orders), the second
  # deriving the chains in reverse order: the bytes must not change.
  run_generator("${WORK_DIR}/first" "${LINKS}")
  list(REVERSE link_list)
  list(JOIN link_list "," reversed)
  run_generator("${WORK_DIR}/second" "${reversed}")
  compare_dirs("${WORK_DIR}/first" "${WORK_DIR}/second"
    "npend-gen is not deterministic: two runs wrote different bytes.")
  message(STATUS "two generator runs wrote identical bytes for link counts ${LINKS}")
else()
  message(FATAL_ERROR "check_generated.cmake: unknown MODE '${MODE}'")
endif()

# Code generation: which link counts are built, where their sources come from, and the
# targets that regenerate and check the committed ones.
#
# Link counts in NPEND_COMMITTED_LINKS are compiled from the committed generated/ folder;
# any other count in NPEND_LINKS is generated into the build tree by npend-gen at build time.

set(NPEND_COMMITTED_LINKS 1 2 3 4 5 6)
set(NPEND_GENERATED_BUILD_DIR "${PROJECT_BINARY_DIR}/generated")

# The models with kernels per link count, one line each:
# "<npend-gen --model>:<file stems>[:<device stems>]", the stems of what
# `npend-gen --links <n> --model <model>` writes: <stem>_<n>.hpp/.cpp (every model also
# writes its Taylor kernels, taylor_<stem>, and the point-mass chain its batch kernels) and,
# for the models of the GPU maps, <device stem>_<n>.cuh (the device functions, never
# compiled into the library: the runtime reads their text).
# Adding a model is a line here (and its row in the generator's emitted_models).
set(NPEND_MODELS
  "point:chain,batch,taylor_chain:gpu_chain"
  "physical:physical,taylor_physical:gpu_physical"
  "cart:cart,taylor_cart")

# _npend_model(<entry> <model var> <stems var> <device stems var>): the parts of an
# NPEND_MODELS entry.
function(_npend_model entry model_var stems_var device_var)
  string(REPLACE ":" ";" parts "${entry}")
  list(GET parts 0 model)
  list(GET parts 1 stems)
  string(REPLACE "," ";" stems "${stems}")
  set(device)
  list(LENGTH parts count)
  if(count GREATER 2)
    list(GET parts 2 device)
    string(REPLACE "," ";" device "${device}")
  endif()
  set(${model_var} "${model}" PARENT_SCOPE)
  set(${stems_var} "${stems}" PARENT_SCOPE)
  set(${device_var} "${device}" PARENT_SCOPE)
endfunction()

# The model names alone (for the drift test, cmake/check_generated.cmake).
set(NPEND_MODEL_NAMES)
foreach(entry IN LISTS NPEND_MODELS)
  _npend_model("${entry}" model stems device)
  list(APPEND NPEND_MODEL_NAMES ${model})
endforeach()

function(_npend_join out)
  list(JOIN ARGN "," joined)
  set(${out} "${joined}" PARENT_SCOPE)
endfunction()

# npend_generated_library(<target> <links>...): a static library with the kernels of the
# given link counts and the index the runtime looks them up in.
# The device functions of the same link counts (gpu_<stem>_<n>.cuh) and of the loop kernels
# (gpu_chain_loop.cuh) are not part of it: their paths are the GLOBAL property
# NPEND_GPU_SOURCES, for the runtime to embed their text. Those generated in the build tree
# are also in NPEND_GPU_SOURCE_DEPENDS, and the target npend_gpu_sources makes them: a rule
# that reads the files names both in its DEPENDS.
function(npend_generated_library target)
  set(links ${ARGN})
  list(REMOVE_DUPLICATES links)
  list(SORT links COMPARE NATURAL)
  set(sources)
  set(headers)
  set(gpu_sources)
  set(gpu_depends)
  set(generated_in_build FALSE)
  foreach(n IN LISTS links)
    if(NOT n MATCHES "^[1-9][0-9]*$")
      message(FATAL_ERROR "NPEND_LINKS: '${n}' is not a positive link count")
    endif()
    if(n IN_LIST NPEND_COMMITTED_LINKS)
      foreach(entry IN LISTS NPEND_MODELS)
        _npend_model("${entry}" model stems device)
        foreach(stem IN LISTS stems)
          list(APPEND sources "${PROJECT_SOURCE_DIR}/generated/${stem}_${n}.cpp")
          list(APPEND headers "${PROJECT_SOURCE_DIR}/generated/${stem}_${n}.hpp")
        endforeach()
        foreach(stem IN LISTS device)
          list(APPEND gpu_sources "${PROJECT_SOURCE_DIR}/generated/${stem}_${n}.cuh")
        endforeach()
      endforeach()
    else()
      if(NOT TARGET npend-gen)
        message(FATAL_ERROR "NPEND_LINKS asks for ${n} links, which are not committed in "
                            "generated/; building them needs the generator "
                            "(-DNPEND_BUILD_GENERATOR=ON, with GiNaC installed).")
      endif()
      foreach(entry IN LISTS NPEND_MODELS)
        _npend_model("${entry}" model stems device)
        set(outputs)
        foreach(stem IN LISTS stems)
          list(APPEND outputs "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.hpp"
               "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.cpp")
          list(APPEND sources "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.cpp")
          list(APPEND headers "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.hpp")
        endforeach()
        foreach(stem IN LISTS device)
          list(APPEND outputs "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.cuh")
          list(APPEND gpu_sources "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.cuh")
          list(APPEND gpu_depends "${NPEND_GENERATED_BUILD_DIR}/${stem}_${n}.cuh")
        endforeach()
        add_custom_command(
          OUTPUT ${outputs}
          COMMAND npend-gen --links ${n} --model ${model} --out "${NPEND_GENERATED_BUILD_DIR}"
          DEPENDS npend-gen
          COMMENT "npend-gen: deriving the ${n}-link chain (${model} model)"
          VERBATIM)
      endforeach()
      set(generated_in_build TRUE)
    endif()
  endforeach()

  set(committed ${NPEND_COMMITTED_LINKS})
  if(links STREQUAL committed)
    foreach(stem chain_index batch_index)
      list(APPEND sources "${PROJECT_SOURCE_DIR}/generated/${stem}.cpp")
      list(APPEND headers "${PROJECT_SOURCE_DIR}/generated/${stem}.hpp")
    endforeach()
  else()
    if(NOT TARGET npend-gen)
      message(FATAL_ERROR "A link-count list other than the committed one needs the generator "
                          "for its index (-DNPEND_BUILD_GENERATOR=ON).")
    endif()
    _npend_join(list_arg ${links})
    set(index "${NPEND_GENERATED_BUILD_DIR}/index/chain_index")
    set(batch_index "${NPEND_GENERATED_BUILD_DIR}/index/batch_index")
    add_custom_command(
      OUTPUT "${index}.hpp" "${index}.cpp" "${batch_index}.hpp" "${batch_index}.cpp"
      COMMAND npend-gen --index ${list_arg} --out "${NPEND_GENERATED_BUILD_DIR}/index"
      DEPENDS npend-gen
      COMMENT "npend-gen: index of link counts ${list_arg}"
      VERBATIM)
    list(APPEND sources "${index}.cpp" "${batch_index}.cpp")
    list(APPEND headers "${index}.hpp" "${batch_index}.hpp")
    set(generated_in_build TRUE)
  endif()
  # The headers to install with the library (cmake/npend_install.cmake).
  set_property(GLOBAL PROPERTY NPEND_GENERATED_HEADERS ${headers})
  # The loop kernels' device functions serve every other link count.
  list(APPEND gpu_sources "${PROJECT_SOURCE_DIR}/generated/gpu_chain_loop.cuh")
  set_property(GLOBAL PROPERTY NPEND_GPU_SOURCES ${gpu_sources})
  set_property(GLOBAL PROPERTY NPEND_GPU_SOURCE_DEPENDS ${gpu_depends})
  # A custom command's outputs are only made for a target of its own directory; this one
  # lets rules of other directories wait for the build-tree device functions.
  add_custom_target(npend_gpu_sources DEPENDS ${gpu_depends})

  # The loop kernels serve every other link count (generated/chain_loop.*).
  list(APPEND sources "${PROJECT_SOURCE_DIR}/generated/chain_loop.cpp")
  list(APPEND headers "${PROJECT_SOURCE_DIR}/generated/chain_loop.hpp")
  add_library(${target} STATIC ${sources})
  add_library(npend::generated ALIAS ${target})
  # The build-tree index must shadow the committed one, so it comes first.
  if(generated_in_build)
    target_include_directories(${target} PUBLIC
      "$<BUILD_INTERFACE:${NPEND_GENERATED_BUILD_DIR}/index>"
      "$<BUILD_INTERFACE:${NPEND_GENERATED_BUILD_DIR}>")
  endif()
  # The generated code includes the runtime's <npend/chain_kernels.hpp> (the contract it
  # fills), never the reverse.
  target_include_directories(${target} PUBLIC
    "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/generated>"
    "$<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/runtime/include>"
    "$<INSTALL_INTERFACE:include/npend/generated>"
    "$<INSTALL_INTERFACE:include>")
  target_compile_features(${target} PUBLIC cxx_std_20)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  # The batch kernels (batch_<n>.cpp): SLEEF's vectorised sincos through the public
  # <npend/batch_math.hpp>, and their lane loops vectorised by `#pragma omp simd`.
  pkg_check_modules(SLEEF REQUIRED IMPORTED_TARGET GLOBAL sleef)
  target_link_libraries(${target} PUBLIC PkgConfig::SLEEF)
  target_compile_options(${target} PRIVATE $<$<CXX_COMPILER_ID:GNU,Clang>:-fopenmp-simd>)
  set(batch_sources ${sources})
  list(FILTER batch_sources INCLUDE REGEX "/batch_[0-9]+\\.cpp$")
  npend_use_wide_vectors(${target} ${batch_sources})
  npend_allocate_registers_in_one_region(${target} ${sources})
  # The kernels and their index once more for each lane ISA variant (cmake/npend_lanes.cmake).
  set(lane_sources ${sources})
  list(FILTER lane_sources INCLUDE REGEX "/batch_([0-9]+|index)\\.cpp$")
  npend_add_lane_variants(${target} SOURCES ${lane_sources} LIBRARIES PkgConfig::SLEEF
                          OPTIONS -Wno-unused-variable)
endfunction()

# Under -march with AVX-512, GCC still prefers 256-bit vectors; the batch kernels and their
# lane loops take full 512-bit ones (1.15x the flip map's lane throughput, measured). Nothing
# changes for targets without AVX-512.
include(CheckCXXCompilerFlag)
check_cxx_compiler_flag(-mprefer-vector-width=512 NPEND_HAS_PREFER_VECTOR_WIDTH)
function(npend_use_wide_vectors target)
  if(NPEND_HAS_PREFER_VECTOR_WIDTH)
    # Their own flag makes the target's precompiled header unusable for them.
    set_source_files_properties(${ARGN} TARGET_DIRECTORY ${target}
                                PROPERTIES COMPILE_OPTIONS -mprefer-vector-width=512
                                           SKIP_PRECOMPILE_HEADERS ON)
  endif()
endfunction()

# The Taylor kernels (taylor_<model>_<n>.cpp) are each one loop over the orders, three times
# (double, long double, dual), with a pointer to every series live across it. GCC's register
# allocation by loop regions took 48 % of the largest one's compile time (taylor_cart_6.cpp,
# 22 s in all); one region for the whole function halves that file's time (all 18 files:
# 96 → 64 CPU-s) and allocates no worse: the triple and six-link chains' Taylor runs were
# 0–8 % faster, with the same bits (measured side by side, 2026-11-29).
function(npend_allocate_registers_in_one_region target)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    return()
  endif()
  set(taylor_sources ${ARGN})
  list(FILTER taylor_sources INCLUDE REGEX "/taylor_[a-z]+_[0-9]+\\.cpp$")
  set_source_files_properties(${taylor_sources} TARGET_DIRECTORY ${target}
                              PROPERTIES COMPILE_OPTIONS -fira-region=one)
endfunction()

# npend_regenerate: rewrite the committed generated/ from the generator (files whose
# content is unchanged are left alone, so nothing rebuilds needlessly).
function(npend_add_regenerate_target)
  _npend_join(list_arg ${NPEND_COMMITTED_LINKS})
  set(commands)
  foreach(model IN LISTS NPEND_MODEL_NAMES)
    list(APPEND commands COMMAND npend-gen --links ${list_arg} --model ${model}
         --out "${PROJECT_SOURCE_DIR}/generated")
  endforeach()
  add_custom_target(npend_regenerate
    ${commands}
    COMMAND npend-gen --index ${list_arg} --loop --out "${PROJECT_SOURCE_DIR}/generated"
    DEPENDS npend-gen
    COMMENT "npend-gen: regenerating generated/ for link counts ${list_arg}"
    VERBATIM)
endfunction()

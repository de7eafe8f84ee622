# The batch lanes' ISA variants. The batch kernels (generated batch_<n>.cpp and their index),
# the lane steppers and the map's lane runs are compiled once for the compiler's own ISA
# (SSE2 in a default x86-64 build) and once more for each of AVX2 (with FMA) and AVX-512F,
# so that a default build runs its maps on the full SIMD width of the CPU it finds
# (runtime/src/analysis/chaos/map_lanes.hpp picks the lanes at run time). A variant's unit is
# a wrapper that includes the source with NPEND_LANE_TARGET set: npend/batch_math.hpp
# switches the code that follows it to the ISA by `#pragma GCC target`, and a variant at or
# below the compiler's own ISA (-march=native) compiles to nothing. GCC on x86-64 only;
# elsewhere the lanes run on the compiler's ISA alone.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_SYSTEM_PROCESSOR MATCHES "^(x86_64|AMD64|amd64)$")
  set(NPEND_LANE_VARIANTS avx2 avx512f)
else()
  set(NPEND_LANE_VARIANTS "")
endif()

# npend_add_lane_variants(<target> SOURCES <file>... LIBRARIES <lib>... [OPTIONS <flag>...]):
# compiles the SOURCES (absolute paths) once per variant, with the target's include
# directories, the LIBRARIES' usage requirements and npend's warnings (and OPTIONS), into
# the target.
function(npend_add_lane_variants target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "SOURCES;LIBRARIES;OPTIONS")
  foreach(isa IN LISTS NPEND_LANE_VARIANTS)
    string(TOUPPER "${isa}" level)
    set(wrappers)
    foreach(source IN LISTS arg_SOURCES)
      get_filename_component(name "${source}" NAME)
      set(wrapper "${CMAKE_CURRENT_BINARY_DIR}/lane_variants/${isa}/${name}")
      file(CONFIGURE OUTPUT "${wrapper}" CONTENT
"// ${name} compiled for the batch lanes' ${isa} variant (cmake/npend_lanes.cmake).
#include <npend/batch_levels.hpp>
#if NPEND_LANE_TARGET > NPEND_LANE_BASELINE
#include \"${source}\"
#endif
" @ONLY)
      list(APPEND wrappers "${wrapper}")
    endforeach()
    set(objects ${target}_lanes_${isa})
    add_library(${objects} OBJECT ${wrappers})
    target_compile_definitions(${objects} PRIVATE NPEND_LANE_TARGET=NPEND_LANE_${level})
    target_include_directories(${objects} PRIVATE
                               "$<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>")
    target_link_libraries(${objects} PRIVATE ${arg_LIBRARIES})
    target_compile_features(${objects} PRIVATE cxx_std_20)
    target_compile_options(${objects} PRIVATE ${NPEND_WARNINGS} ${arg_OPTIONS}
                                              $<$<CXX_COMPILER_ID:GNU>:-fopenmp-simd>)
    set_target_properties(${objects} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    target_sources(${target} PRIVATE $<TARGET_OBJECTS:${objects}>)
  endforeach()
endfunction()

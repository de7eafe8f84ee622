// The instruction-set levels of the batch kernels and lanes, and the one the compiler targets
// by itself (its -march). A lane variant's translation unit (cmake/npend_lanes.cmake) is
// compiled with NPEND_LANE_TARGET set to a level; npend/batch_math.hpp switches it to that
// ISA where it lies above the compiler's own, and where it does not, the variant is not
// needed and its unit compiles to nothing.
#pragma once

// The ISA levels, lowest first.
#define NPEND_LANE_SSE2 1
#define NPEND_LANE_AVX 2
#define NPEND_LANE_AVX2 3  // AVX2 with FMA
#define NPEND_LANE_AVX512F 4

// The level the compiler targets anyway.
#if defined(__AVX512F__)
#define NPEND_LANE_BASELINE NPEND_LANE_AVX512F
#elif defined(__AVX2__) && defined(__FMA__)
#define NPEND_LANE_BASELINE NPEND_LANE_AVX2
#elif defined(__AVX__)
#define NPEND_LANE_BASELINE NPEND_LANE_AVX
#else
#define NPEND_LANE_BASELINE NPEND_LANE_SSE2
#endif

// The lane width of the batch kernels and their vectorised sine and cosine.
//
// The batch kernels (generated batch_<n>.cpp) work on W states at once in structure-of-arrays
// layout, v[i*W + lane]. W is fixed at compile time by the target ISA: 8 lanes with AVX-512F,
// 4 with AVX (or AVX2 and FMA), 2 with SSE2 (every x86-64). The sines and cosines come from
// SLEEF's 1-ulp sincos for that ISA (with 2 lanes, the best variant of the CPU at run time;
// its maximum error is 1 ulp; tests/generated/test_batch_math.cpp checks it against std::sin
// and std::cos); the rest of a kernel is +, -, *, / over the lanes in `#pragma omp simd`
// loops, so every lane's arithmetic is the same whichever slot it sits in.
//
// The target ISA is the compiler's (its -march), unless the translation unit is one of the
// lanes' variants: compiled with NPEND_LANE_TARGET = NPEND_LANE_AVX2 or NPEND_LANE_AVX512F
// above the compiler's own ISA, this header switches what follows it to that ISA with
// `#pragma GCC target` (and never switches back). Such a unit includes this header after
// every other header that is not itself lane code: what follows is compiled for an ISA the
// CPU may lack, and the inline functions of a header first seen there would be compiled for
// it too, and could be the copy the linker keeps for every caller
// (tests/runtime/chaos/check_lane_objects.py checks the objects for that). Templates
// declared before the switch keep the baseline ISA wherever they are instantiated.
//
// Every definition here and in the kernels sits in an inline namespace named after the ISA,
// so that one program holds the kernels and lanes of several ISAs (the runtime picks one
// when a map runs: runtime/src/analysis/chaos/map_lanes.hpp), and a consumer built with
// -march=native against a baseline library holds two distinct batch_sincos rather than one,
// picked by the linker, that half of its callers would call with the wrong lane count.
#pragma once

#include <sleef.h>

// All of GCC's intrinsics, whatever the compiler's ISA: a variant calls those of its own.
#if defined(__SSE2__)
#include <immintrin.h>
#else
#error "npend's batch kernels need x86-64 (SSE2 or later)"
#endif

#include "npend/batch_levels.hpp"

#if defined(NPEND_LANE_TARGET) && NPEND_LANE_TARGET > NPEND_LANE_BASELINE
#if !defined(__GNUC__) || defined(__clang__)
#error "npend's lane variants need GCC's #pragma GCC target"
#endif
#define NPEND_BATCH_LEVEL NPEND_LANE_TARGET
// GCC does not define __AVX2__ and the like under the pragma in C++, hence the levels.
#if NPEND_LANE_TARGET == NPEND_LANE_AVX512F
#pragma GCC target("avx512f,avx2,fma,prefer-vector-width=512")
#elif NPEND_LANE_TARGET == NPEND_LANE_AVX2
#pragma GCC target("avx2,fma")
#else
#error "NPEND_LANE_TARGET: a lane variant is NPEND_LANE_AVX2 or NPEND_LANE_AVX512F"
#endif
#else
#define NPEND_BATCH_LEVEL NPEND_LANE_BASELINE
#endif

#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F
#define NPEND_BATCH_ISA_NAMESPACE isa_avx512f
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX2
#define NPEND_BATCH_ISA_NAMESPACE isa_avx2
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX
#define NPEND_BATCH_ISA_NAMESPACE isa_avx
#else
#define NPEND_BATCH_ISA_NAMESPACE isa_sse2
#endif

// sleef.h declares its 256- and 512-bit functions only where the compiler's own ISA has
// them; a variant above it declares the one it calls, with SLEEF's own types.
#if NPEND_BATCH_LEVEL >= NPEND_LANE_AVX2 && !defined(Sleef___m256d_2_DEFINED)
typedef struct {
  __m256d x, y;
} Sleef___m256d_2;
#define Sleef___m256d_2_DEFINED
#endif
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX2 && !defined(__AVX__)
extern "C" Sleef___m256d_2 Sleef_sincosd4_u10avx2(__m256d);
#endif
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F && !defined(Sleef___m512d_2_DEFINED)
typedef struct {
  __m512d x, y;
} Sleef___m512d_2;
#define Sleef___m512d_2_DEFINED
#endif
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F && !defined(__AVX512F__)
extern "C" Sleef___m512d_2 Sleef_sincosd8_u10avx512f(__m512d);
#endif

namespace npend {
inline namespace NPEND_BATCH_ISA_NAMESPACE {

/// Lanes of a batch kernel: 8 (AVX-512F), 4 (AVX, AVX2) or 2 (SSE2).
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F
inline constexpr int batch_width = 8;
#elif NPEND_BATCH_LEVEL >= NPEND_LANE_AVX
inline constexpr int batch_width = 4;
#else
inline constexpr int batch_width = 2;
#endif

/// Blocks of batch_width lanes whose sines and cosines a kernel takes before their
/// arithmetic: each block's rhs ends in a division whose result the rest waits for, and with
/// the sines of several blocks at hand the processor overlaps their divisions.
inline constexpr int batch_blocks = 4;

/// The instruction set the batch kernels were compiled for: "avx512f", "avx2" (AVX2 with
/// FMA), "avx" or "sse2".
constexpr const char* batch_isa() noexcept {
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F
  return "avx512f";
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX2
  return "avx2";
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX
  return "avx";
#else
  return "sse2";
#endif
}

/// s[l] = sin(x[l]), c[l] = cos(x[l]) for the batch_width lanes l (arrays of batch_width,
/// any alignment), by SLEEF's 1-ulp sincos for batch_isa() (for "sse2", the best 2-lane
/// variant of the CPU it runs on). Finite x of any size (SLEEF reduces the argument
/// exactly); NaN for ±inf or NaN.
inline void batch_sincos(const double* x, double* s, double* c) noexcept {
#if NPEND_BATCH_LEVEL == NPEND_LANE_AVX512F
  const Sleef___m512d_2 r = Sleef_sincosd8_u10avx512f(_mm512_loadu_pd(x));
  _mm512_storeu_pd(s, r.x);
  _mm512_storeu_pd(c, r.y);
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX2
  const Sleef___m256d_2 r = Sleef_sincosd4_u10avx2(_mm256_loadu_pd(x));
  _mm256_storeu_pd(s, r.x);
  _mm256_storeu_pd(c, r.y);
#elif NPEND_BATCH_LEVEL == NPEND_LANE_AVX
  const Sleef___m256d_2 r = Sleef_sincosd4_u10avx(_mm256_loadu_pd(x));
  _mm256_storeu_pd(s, r.x);
  _mm256_storeu_pd(c, r.y);
#else
  // SLEEF's dispatcher: the best 2-lane variant the CPU has (SSE4.1, or AVX2 with FMA on
  // 128-bit vectors), chosen once at run time. Its plain SSE2 variant, without SSE4.1's
  // rounding instruction, takes four times as long (44 ns a call against 10 here), longer
  // than std::sin and std::cos of both lanes. glibc picks its std::sin by the CPU too.
  const Sleef___m128d_2 r = Sleef_sincosd2_u10(_mm_loadu_pd(x));
  _mm_storeu_pd(s, r.x);
  _mm_storeu_pd(c, r.y);
#endif
}

}  // namespace NPEND_BATCH_ISA_NAMESPACE
}  // namespace npend

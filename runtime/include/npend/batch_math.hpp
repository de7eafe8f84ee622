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
// Every translation unit of one build sees the same W: the kernels and their callers must be
// compiled for the same target (the table entry records W, and the runtime checks it).
#pragma once

#include <sleef.h>

#if defined(__AVX512F__) || defined(__AVX__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#else
#error "npend's batch kernels need x86-64 (SSE2 or later)"
#endif

// The definitions below differ with the target ISA, so they sit in an inline namespace named
// after it: a program whose parts are compiled for different targets (a consumer built with
// -march=native against a baseline library) then holds two distinct batch_sincos rather than
// one, picked by the linker, that half of its callers would call with the wrong lane count.
#if defined(__AVX512F__)
#define NPEND_BATCH_ISA_NAMESPACE isa_avx512f
#elif defined(__AVX2__) && defined(__FMA__)
#define NPEND_BATCH_ISA_NAMESPACE isa_avx2
#elif defined(__AVX__)
#define NPEND_BATCH_ISA_NAMESPACE isa_avx
#else
#define NPEND_BATCH_ISA_NAMESPACE isa_sse2
#endif

namespace npend {
inline namespace NPEND_BATCH_ISA_NAMESPACE {

/// Lanes of a batch kernel: 8 (AVX-512F), 4 (AVX, AVX2) or 2 (SSE2).
#if defined(__AVX512F__)
inline constexpr int batch_width = 8;
#elif defined(__AVX__)
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
#if defined(__AVX512F__)
  return "avx512f";
#elif defined(__AVX2__) && defined(__FMA__)
  return "avx2";
#elif defined(__AVX__)
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
#if defined(__AVX512F__)
  const Sleef___m512d_2 r = Sleef_sincosd8_u10avx512f(_mm512_loadu_pd(x));
  _mm512_storeu_pd(s, r.x);
  _mm512_storeu_pd(c, r.y);
#elif defined(__AVX2__) && defined(__FMA__)
  const Sleef___m256d_2 r = Sleef_sincosd4_u10avx2(_mm256_loadu_pd(x));
  _mm256_storeu_pd(s, r.x);
  _mm256_storeu_pd(c, r.y);
#elif defined(__AVX__)
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

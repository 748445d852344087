#pragma once

// Which versions of the vectorised loops this build compiles (private to the library; the
// same for core/simd.cpp, which chooses, and the env loops, which have the versions), and the
// attributes that compile each.
//
// - scalar: the loop as written, one element at a time (GCC's optimize attribute turns the
//   vectoriser off for that function; clang, the fuzz build, has no such attribute and compiles
//   it as the baseline)
// - baseline: as the build compiles for the architecture (SSE2 on x86-64, NEON on aarch64)
// - avx2, avx512: x86-64 with GCC, the same source compiled for x86-64-v3 and x86-64-v4
//   (CMake: PLUMETRACE_VECTOR_CLONES=OFF leaves both out, PLUMETRACE_AVX512=OFF the second)
//
// PLUMETRACE_SIMD_VERSIONS names plumetrace::simd::Path: its users include
// plumetrace/core/simd.hpp (not included here, as simd.cpp includes this file).

#if defined(__GNUC__) && !defined(__clang__)
#define PLUMETRACE_SCALAR_TARGET [[gnu::optimize("no-tree-vectorize")]]
#else
#define PLUMETRACE_SCALAR_TARGET
#endif

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(PLUMETRACE_NO_VECTOR_CLONES)
#define PLUMETRACE_SIMD_AVX2 1
#define PLUMETRACE_AVX2_TARGET __attribute__((target("arch=x86-64-v3")))
#if !defined(PLUMETRACE_NO_AVX512)
#define PLUMETRACE_SIMD_AVX512 1
#define PLUMETRACE_AVX512_TARGET __attribute__((target("arch=x86-64-v4")))
#endif
#endif

#if defined(PLUMETRACE_SIMD_AVX2)
#define PLUMETRACE_IF_AVX2(...) __VA_ARGS__
#else
#define PLUMETRACE_IF_AVX2(...)
#endif
#if defined(PLUMETRACE_SIMD_AVX512)
#define PLUMETRACE_IF_AVX512(...) __VA_ARGS__
#else
#define PLUMETRACE_IF_AVX512(...)
#endif
#define PLUMETRACE_UNPAREN(...) __VA_ARGS__

// PLUMETRACE_SIMD_VERSIONS(NAME, (PARAMS), (ARGS)) defines void NAME(simd::Path path, PARAMS),
// which runs NAME_body<path>(ARGS) as compiled for that path, and NAME_for(path), which returns
// that version (to call it many times, or with no more arguments than PARAMS): one function per
// path this build has (NAME_scalar, NAME_baseline, NAME_avx2, NAME_avx512, each with its
// target), the body inlined into each (declare it [[gnu::always_inline]] and
// template <simd::Path kPath>). A path this build lacks gets the baseline; callers pass
// simd::active() or an available path.
#define PLUMETRACE_SIMD_VERSIONS(NAME, PARAMS, ARGS)                                            \
  PLUMETRACE_SCALAR_TARGET static void NAME##_scalar PARAMS {                                   \
    NAME##_body<::plumetrace::simd::Path::kScalar> ARGS;                                        \
  }                                                                                             \
  static void NAME##_baseline PARAMS { NAME##_body<::plumetrace::simd::Path::kBaseline> ARGS; } \
  PLUMETRACE_IF_AVX2(PLUMETRACE_AVX2_TARGET static void NAME##_avx2 PARAMS {                    \
    NAME##_body<::plumetrace::simd::Path::kAvx2> ARGS;                                          \
  })                                                                                            \
  PLUMETRACE_IF_AVX512(PLUMETRACE_AVX512_TARGET static void NAME##_avx512 PARAMS {              \
    NAME##_body<::plumetrace::simd::Path::kAvx512> ARGS;                                        \
  })                                                                                            \
  auto NAME##_for(::plumetrace::simd::Path path)->decltype(&NAME##_baseline) {                  \
    switch (path) {                                                                             \
      case ::plumetrace::simd::Path::kScalar:                                                   \
        return &NAME##_scalar;                                                                  \
        PLUMETRACE_IF_AVX2(case ::plumetrace::simd::Path::kAvx2 : return &NAME##_avx2;)         \
        PLUMETRACE_IF_AVX512(case ::plumetrace::simd::Path::kAvx512 : return &NAME##_avx512;)   \
      default:                                                                                  \
        return &NAME##_baseline;                                                                \
    }                                                                                           \
  }                                                                                             \
  void NAME(::plumetrace::simd::Path path, PLUMETRACE_UNPAREN PARAMS) { NAME##_for(path) ARGS; }

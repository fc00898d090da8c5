#pragma once
// FP_HD marks the per-pixel maths that both backends compile: the CPU passes call it from their
// tile loops, the CUDA kernels (the `.cu` file beside a pass) from one thread per pixel, so the
// two run the same arithmetic. nvcc builds with -fmad=false and IEEE division and square root,
// matching g++'s ISO C++ mode (no FMA contraction).
#if defined(__CUDACC__)
#define FP_HD __host__ __device__
#else
#define FP_HD
#endif

// FP_HOT_INLINE: a function of a per-pixel loop that the host compiler must inline. g++ weighs
// inlining per caller and per number of callers: in the larger FP_HD templates (a tracer's texel,
// a light loop) it kept normalize() an out-of-line call (3.6 % of rt_reflections' CPU time), and
// once RTAO's set-up had a second caller (the BVH path's kernel) it stopped inlining it into the
// Embree path's tile loop (12 % slower). Inlining changes no result (no contraction either way).
#if defined(__CUDA_ARCH__)
#define FP_HOT_INLINE inline
#else
#define FP_HOT_INLINE __attribute__((always_inline)) inline
#endif

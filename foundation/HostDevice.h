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

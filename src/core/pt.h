// The host/device macro set: every function a stage calls compiles for the CPU backend
// (plain C++) and, when nvcc sees it, for the GPU too. Nothing else in src/ knows about CUDA.
#pragma once

#if defined(__CUDACC__)
#define PT_HD __host__ __device__
#define PT_DEVICE_COMPILE 1
#else
#define PT_HD
#define PT_DEVICE_COMPILE 0
#endif

#define PT_HDI PT_HD inline

// For the few hot bodies of ray traversal (node and triangle tests): GCC's heuristics left them
// as calls on the host, where the per-ray constants then go through memory. nvcc inlines them
// anyway; forcing it there too keeps one definition.
#if defined(__CUDACC__)
#define PT_HDI_HOT PT_HD __forceinline__
#elif defined(__GNUC__)
#define PT_HDI_HOT inline __attribute__((always_inline))
#else
#define PT_HDI_HOT inline
#endif

#if defined(__CUDA_ARCH__)
#define PT_IS_GPU_CODE 1
#else
#define PT_IS_GPU_CODE 0
#endif

#include <cstdint>

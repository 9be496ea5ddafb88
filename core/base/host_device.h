// Marks functions that CUDA compiles for both host and device; plain C++ sees nothing.
// Math shared by the CPU core and the CUDA kernels is written once, in headers that use this.
#pragma once

#if defined(__CUDACC__)
#define TESSERA_HD __host__ __device__ __forceinline__
#else
#define TESSERA_HD inline
#endif

// The cubic Bernstein basis B³_i(t) = C(3,i) tᶦ (1−t)³⁻ᶦ and its derivative, written once in the
// subset that C++, CUDA and GLSL share: core evaluates Bézier pieces with it in double
// (core/math/bicubic.h), the shaders in float (shaders/include/bezier.glsl includes this file through
// glslc's -I at the repository root). The operations are in one order everywhere, so a CPU path
// and a GPU path of the same precision round alike.
#ifndef TESSERA_CUBIC_BERNSTEIN_H
#define TESSERA_CUBIC_BERNSTEIN_H

#ifdef __cplusplus
#include "core/base/host_device.h"
#define TESSERA_BASIS_FN TESSERA_HD
#define TESSERA_BASIS_REAL double
#define TESSERA_BASIS_OUT
#else
#define TESSERA_BASIS_FN
#define TESSERA_BASIS_REAL float
#define TESSERA_BASIS_OUT out
#endif

TESSERA_BASIS_FN void cubicBernstein(TESSERA_BASIS_REAL t, TESSERA_BASIS_OUT TESSERA_BASIS_REAL w[4],
                                     TESSERA_BASIS_OUT TESSERA_BASIS_REAL dw[4]) {
  TESSERA_BASIS_REAL s = 1.0 - t;
  w[0] = s * s * s;
  w[1] = 3.0 * t * s * s;
  w[2] = 3.0 * t * t * s;
  w[3] = t * t * t;
  dw[0] = -3.0 * s * s;
  dw[1] = 3.0 * s * s - 6.0 * t * s;
  dw[2] = 6.0 * t * s - 3.0 * t * t;
  dw[3] = 3.0 * t * t;
}

#undef TESSERA_BASIS_FN
#undef TESSERA_BASIS_REAL
#undef TESSERA_BASIS_OUT

#endif

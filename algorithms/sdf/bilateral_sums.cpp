#include "sdf/bilateral_sums.h"

#include <math.h>

// AVX2 and FMA beside the baseline on x86-64; elsewhere, the baseline.
#if defined(__x86_64__)
#define CGVIEW_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CGVIEW_VECTOR_CLONES
#endif

namespace cgview::sdf {

// Plain loops, nothing inline from a library: the AVX2 clone shares no code
// with the rest of the program (an inline function compiled twice, for two
// instruction sets, would be one function to the linker).
CGVIEW_VECTOR_CLONES float squared_deviation(const float* x, std::size_t n, float c) {
  float s = 0;
#pragma omp simd reduction(+ : s)
  for (std::size_t k = 0; k < n; ++k) s += (x[k] - c) * (x[k] - c);
  return s;
}

CGVIEW_VECTOR_CLONES void weighted_sums(const float* x, const float* ring, std::size_t n, float c, float inv,
                                        float& sum, float& weights) {
  float s = 0, w = 0;
#pragma omp simd reduction(+ : s, w)
  for (std::size_t k = 0; k < n; ++k) {
    const float d = x[k] - c;
    const float q = expf(-(ring[k] + inv * d * d));
    s += q * x[k];
    w += q;
  }
  sum = s;
  weights = w;
}

CGVIEW_VECTOR_CLONES void scaled_weighted_sums(const float* x, const float* scale, std::size_t n, float c, float inv,
                                               float& sum, float& weights) {
  float s = 0, w = 0;
#pragma omp simd reduction(+ : s, w)
  for (std::size_t k = 0; k < n; ++k) {
    const float d = x[k] - c;
    const float q = scale[k] * expf(-(inv * d * d));
    s += q * x[k];
    w += q;
  }
  sum = s;
  weights = w;
}

}  // namespace cgview::sdf

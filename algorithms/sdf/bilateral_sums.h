// The bilateral filter's sums over one face's window, in float and in vector
// instructions: glibc's vector exp (libmvec), and AVX2 where the processor
// has it (chosen when the program starts).  Compiled apart, with
// -ffast-math: the values here are never NaN, and the order of the sums may
// change with the vector width.
#pragma once

#include <cstddef>

namespace cgview::sdf {

// sum_k (x_k - c)^2.
float squared_deviation(const float* x, std::size_t n, float c);

// w_k = exp(-(ring_k + inv (x_k - c)^2)); returns sum_k w_k x_k in `sum` and
// sum_k w_k in `weights`.
void weighted_sums(const float* x, const float* ring, std::size_t n, float c, float inv, float& sum, float& weights);

// The same with the weights' factors as they are: w_k = scale_k exp(-inv (x_k
// - c)^2) (no logarithm a term to take beforehand).
void scaled_weighted_sums(const float* x, const float* scale, std::size_t n, float c, float inv, float& sum,
                          float& weights);

}  // namespace cgview::sdf

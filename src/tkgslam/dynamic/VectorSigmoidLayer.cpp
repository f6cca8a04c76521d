#include "tkgslam/dynamic/VectorSigmoidLayer.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/dynamic/ElementwiseLayer.h"

namespace tkgslam::dynamic {

namespace {

// GCC vector types: eight floats, compiled to two SSE2 or one AVX2 register.
typedef float Floats __attribute__((vector_size(32)));
typedef int Ints __attribute__((vector_size(32)));
typedef unsigned UInts __attribute__((vector_size(32)));
constexpr int kLanes = 8;

// exp(-x) by range reduction to r in [-ln2/2, ln2/2] (exp = 2^n e^r) and Cephes' polynomial for
// e^r, then 1 / (1 + exp(-x)). -x is clamped to [-87, 88], where 2^n stays a normal float: beyond it
// the sigmoid is 0 or 1 to float precision anyway.
// Inlined into a baseline and an AVX2 build below. Neither may use FMA (the "avx2" target does not
// include it), so a * b + c is rounded twice in both and they give the same bits.
inline __attribute__((always_inline)) void sigmoidBlocksBody(const float* x, float* y, size_t blocks) {
  for (size_t b = 0; b < blocks; ++b) {
    Floats v;
    std::memcpy(&v, x + b * kLanes, sizeof v);
    Floats t = -v;
    t = t > (Floats{} + 88.f) ? (Floats{} + 88.f) : t;
    t = t < (Floats{} + -87.f) ? (Floats{} + -87.f) : t;
    const Floats n = (t * 1.44269504088896341f + 12582912.f) - 12582912.f;  // round(t / ln 2)
    Floats r = t - n * 0.693359375f;  // ln 2 in two parts, the first exact in float
    r = r - n * -2.12194440e-4f;
    Floats p = (Floats{} + 1.9875691500e-4f);
    p = p * r + 1.3981999507e-3f;
    p = p * r + 8.3334519073e-3f;
    p = p * r + 4.1665795894e-2f;
    p = p * r + 1.6666665459e-1f;
    p = p * r + 5.0000001201e-1f;
    p = p * r * r + r + 1.f;
    const Ints biased = __builtin_convertvector(n, Ints) + 127;  // 1..254 for the clamped range
    const UInts exponent = UInts(biased) << 23;                  // unsigned: no shift of a negative (NaN)
    Floats two_n;
    std::memcpy(&two_n, &exponent, sizeof two_n);
    const Floats s = 1.f / (1.f + p * two_n);
    std::memcpy(y + b * kLanes, &s, sizeof s);
  }
}

__attribute__((target("avx2"))) void sigmoidBlocksAvx2(const float* x, float* y, size_t blocks) {
  sigmoidBlocksBody(x, y, blocks);
}

void sigmoidBlocksBaseline(const float* x, float* y, size_t blocks) { sigmoidBlocksBody(x, y, blocks); }

// Chosen once at run time by a plain branch, not an ifunc (GCC's target_clones): ifunc resolvers
// run while the program is being relocated, before ThreadSanitizer's runtime is up, and crash it.
void sigmoidBlocks(const float* x, float* y, size_t blocks) {
  static const bool avx2 = __builtin_cpu_supports("avx2");
  (avx2 ? sigmoidBlocksAvx2 : sigmoidBlocksBaseline)(x, y, blocks);
}

}  // namespace

void vectorSigmoid(const float* x, float* y, size_t n) {
  const size_t whole = n / kLanes;
  sigmoidBlocks(x, y, whole);
  const size_t done = whole * kLanes;
  if (done == n) return;
  float tail[kLanes] = {};  // the last few values through the same code, so every value gets the same function
  std::copy(x + done, x + n, tail);
  sigmoidBlocks(tail, tail, 1);
  std::copy(tail, tail + (n - done), y + done);
}

cv::Ptr<cv::dnn::Layer> createVectorSigmoidLayer(cv::dnn::LayerParams& params) {
  return cv::Ptr<cv::dnn::Layer>(new ElementwiseLayer<cv::dnn::Layer, vectorSigmoid>(params));
}

}  // namespace tkgslam::dynamic

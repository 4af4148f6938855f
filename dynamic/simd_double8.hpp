#pragma once
// Eight doubles in an AVX-512 register, with the operations the law templates use (the double
// versions' IEEE operations lane by lane; no FMA). For the translation units compiled with
// -mavx512f only (contact_forces_simd.cpp, integrator_simd.cpp): everything has internal
// linkage, so no AVX-512 code can be linked into a function the rest of the program calls.
#if defined(__x86_64__)
#include <immintrin.h>

namespace granstab::dynamic::simd {
namespace {

struct Mask8 {
  __mmask8 m;
  friend Mask8 operator&(Mask8 a, Mask8 b) { return {static_cast<__mmask8>(a.m & b.m)}; }
  friend Mask8 operator|(Mask8 a, Mask8 b) { return {static_cast<__mmask8>(a.m | b.m)}; }
  int bits() const { return m; }
};

struct Double8 {
  __m512d v;
  Double8() = default;
  Double8(__m512d a) : v(a) {}
  Double8(double a) : v(_mm512_set1_pd(a)) {}
  friend Double8 operator+(Double8 a, Double8 b) { return _mm512_add_pd(a.v, b.v); }
  friend Double8 operator-(Double8 a, Double8 b) { return _mm512_sub_pd(a.v, b.v); }
  friend Double8 operator*(Double8 a, Double8 b) { return _mm512_mul_pd(a.v, b.v); }
  friend Double8 operator/(Double8 a, Double8 b) { return _mm512_div_pd(a.v, b.v); }
  friend Double8 operator-(Double8 a) { return _mm512_xor_pd(a.v, _mm512_set1_pd(-0.0)); }
  friend Mask8 operator>(Double8 a, Double8 b) {
    return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)};
  }
  friend Mask8 operator<(Double8 a, Double8 b) {
    return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)};
  }
  friend Mask8 operator<=(Double8 a, Double8 b) {
    return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LE_OQ)};
  }
  friend Mask8 operator>=(Double8 a, Double8 b) {
    return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GE_OQ)};
  }
  friend Double8 sqrt(Double8 a) { return _mm512_sqrt_pd(a.v); }
  friend Double8 abs(Double8 a) { return _mm512_andnot_pd(_mm512_set1_pd(-0.0), a.v); }
  friend Double8 copysign(Double8 magnitude, Double8 sign) {
    const __m512d s = _mm512_set1_pd(-0.0);
    return _mm512_or_pd(_mm512_andnot_pd(s, magnitude.v), _mm512_and_pd(s, sign.v));
  }
  friend Double8 select(Mask8 c, Double8 a, Double8 b) {
    return _mm512_mask_blend_pd(c.m, b.v, a.v);
  }
};

inline Double8 gather(const double* base, __m256i index) {
  return _mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xFF, index, base, 8);
}

}  // namespace
}  // namespace granstab::dynamic::simd
#endif

// The drift's SIMD kernel (integrator_simd.hpp). Compiled as contact_forces_simd.cpp (AVX-512,
// -ffp-contract=off): every lane does the IEEE operations of drift_disk<double> in the same
// order, and the largest displacement is the same number whatever order the lanes are compared
// in (squares: no -0; a NaN lane is passed over, as std::max(max, NaN) does). Only kick_drift has
// external linkage.
#include "integrator_simd.hpp"

#if defined(__x86_64__)
#include "simd_double8.hpp"

namespace granstab::dynamic::simd {
namespace {

template <bool Periodic, bool Full>
[[gnu::always_inline]] inline __m512d drift8(const DriftBlock& b, const DriftConstants& k, int i,
                                             __mmask8 m, __m512d max_d2) {
  // Plain loads and stores for whole vectors: masked ones cost more on some CPUs.
  const auto load = [&](const double* a) {
    return Full ? Double8(_mm512_loadu_pd(a + i)) : Double8(_mm512_maskz_loadu_pd(m, a + i));
  };
  const auto store = [&](double* a, Double8 v) {
    if constexpr (Full) {
      _mm512_storeu_pd(a + i, v.v);
    } else {
      _mm512_mask_storeu_pd(a + i, m, v.v);
    }
  };
  const Drifted<Double8> o = drift_disk<Periodic>(
      k, load(b.x), load(b.y), load(b.vx), load(b.vy), load(b.omega), load(b.theta), load(b.fx),
      load(b.fy), load(b.fvx), load(b.fvy), load(b.torque), load(b.inv_mass), load(b.inv_inertia),
      load(b.ref_x), load(b.ref_y));
  store(b.vx, o.vx);
  store(b.vy, o.vy);
  store(b.vpx, o.vpx);
  store(b.vpy, o.vpy);
  store(b.omega, o.omega);
  for (double* f : {b.fx, b.fy, b.fvx, b.fvy, b.torque}) store(f, Double8(0.0));
  store(b.x, o.x);
  store(b.y, o.y);
  store(b.theta, o.theta);
  // std::max(max_d2, d2) lane by lane: MAXPD(d2, max) is d2 > max ? d2 : max.
  return _mm512_mask_max_pd(max_d2, m, o.d2.v, max_d2);
}

template <bool Periodic>
double kick_drift(const DriftBlock& b, const DriftConstants& k, int first, int end) {
  __m512d max_d2 = _mm512_setzero_pd();
  int i = first;
  for (; i + 8 <= end; i += 8) max_d2 = drift8<Periodic, true>(b, k, i, 0xFF, max_d2);
  if (i < end) {
    const __mmask8 m = static_cast<__mmask8>((1u << (end - i)) - 1u);
    max_d2 = drift8<Periodic, false>(b, k, i, m, max_d2);
  }
  // (Not _mm512_reduce_max_pd: GCC 12's header trips -Wuninitialized.)
  alignas(64) double lanes[8];
  _mm512_store_pd(lanes, max_d2);
  double out = lanes[0];
  for (int l = 1; l < 8; ++l) out = lanes[l] > out ? lanes[l] : out;
  return out;
}

}  // namespace

double kick_drift(const DriftBlock& b, const DriftConstants& k, bool periodic, int first, int end) {
  return periodic ? kick_drift<true>(b, k, first, end) : kick_drift<false>(b, k, first, end);
}

}  // namespace granstab::dynamic::simd
#else
namespace granstab::dynamic::simd {
double kick_drift(const DriftBlock&, const DriftConstants&, bool, int, int) { return 0.0; }
}  // namespace granstab::dynamic::simd
#endif

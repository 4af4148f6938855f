// The force pass's SIMD kernel (contact_forces_simd.hpp). Compiled with -mavx512f (dq, bw, vl)
// -ffp-contract=off (dynamic/CMakeLists.txt): every lane does the IEEE operations of the double
// instantiation of the same templates in the same order, so the results are the same bits.
// Everything here has internal linkage except pair_law (checked in dynamic/CMakeLists.txt's
// comment: `nm` of this object defines no weak symbol), so no AVX-512 code leaks into functions
// the rest of the program calls.
#include "contact_forces_simd.hpp"

#if defined(__x86_64__)
#include "simd_double8.hpp"

namespace granstab::dynamic::simd {
namespace {

template <bool Periodic>
void pair_law(const PairBlock& b, const PairLawConstants& k, double l1, double l2, int begin,
              int end) {
  const double half_l1 = 0.5 * l1, half_l2 = 0.5 * l2;
  for (int p = begin; p < end; p += lanes) {
    const int s = p - begin;
    const int left = end - p;
    const __mmask8 valid = left >= 8 ? 0xFF : static_cast<__mmask8>((1u << left) - 1u);
    const Mask8 in_range{valid};
    const __m256i i = _mm256_maskz_loadu_epi32(valid, b.pair_i + p);
    const __m256i j = _mm256_maskz_loadu_epi32(valid, b.pair_j + p);
    Double8 dx = gather(b.x, j) - gather(b.x, i);
    Double8 dy = gather(b.y, j) - gather(b.y, i);
    if constexpr (Periodic) {
      dx = minimum_image(dx, l1, half_l1);
      dy = minimum_image(dy, l2, half_l2);
    }
    const Double8 ri = gather(b.radius, i), rj = gather(b.radius, j);
    const Double8 reach = ri + rj;
    const Mask8 closed =
        Mask8{_mm512_cmp_pd_mask((dx * dx + dy * dy).v, (reach * reach).v, _CMP_NGE_UQ)} & in_range;
    _mm_storel_epi64(reinterpret_cast<__m128i*>(b.closed + s), _mm_maskz_set1_epi8(closed.m, 1));
    if (closed.m == 0) continue;
    const Double8 f_n_before = _mm512_maskz_loadu_pd(valid, b.f_n + p);
    const auto keep_state = [&](Double8 delta_t, Double8 f_n, Double8 nx, Double8 ny) {
      _mm512_mask_storeu_pd(b.delta_t + p, closed.m, delta_t.v);
      _mm512_mask_storeu_pd(b.f_n + p, closed.m, f_n.v);
      _mm512_mask_storeu_pd(b.nx + p, closed.m, nx.v);
      _mm512_mask_storeu_pd(b.ny + p, closed.m, ny.v);
      _mm512_mask_storeu_pd(b.lx + p, closed.m, dx.v);
      _mm512_mask_storeu_pd(b.ly + p, closed.m, dy.v);
    };
    const ClosedPair<Double8> c = closed_pair_law<Periodic>(
        k, dx, dy, ri, rj, gather(b.vx, i), gather(b.vy, i), gather(b.omega, i), gather(b.vx, j),
        gather(b.vy, j), gather(b.omega, j), gather(b.vvx, i), gather(b.vvy, i), gather(b.vvx, j),
        gather(b.vvy, j), Double8(_mm512_maskz_loadu_pd(valid, b.alpha + p)),
        Double8(_mm512_maskz_loadu_pd(valid, b.delta_t + p)), f_n_before > 0.0, keep_state);
    _mm512_storeu_pd(b.fx + s, c.fx.v);
    _mm512_storeu_pd(b.fy + s, c.fy.v);
    _mm512_storeu_pd(b.fvx + s, c.fvx.v);
    _mm512_storeu_pd(b.fvy + s, c.fvy.v);
    _mm512_storeu_pd(b.torque_i + s, c.torque_i.v);
    _mm512_storeu_pd(b.torque_j + s, c.torque_j.v);
  }
}

}  // namespace

void pair_law(const PairBlock& b, const PairLawConstants& k, bool periodic, double l1, double l2,
              int begin, int end) {
  if (periodic) {
    pair_law<true>(b, k, l1, l2, begin, end);
  } else {
    pair_law<false>(b, k, l1, l2, begin, end);
  }
}

}  // namespace granstab::dynamic::simd
#else
namespace granstab::dynamic::simd {
void pair_law(const PairBlock&, const PairLawConstants&, bool, double, double, int, int) {}
}  // namespace granstab::dynamic::simd
#endif

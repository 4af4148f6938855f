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
int pair_law(const PairBlock& b, const PairLawConstants& k, double l1, double l2, int begin,
             int end) {
  const double half_l1 = 0.5 * l1, half_l2 = 0.5 * l2;
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  int touched = 0;
  for (int p = begin; p < end; p += lanes) {
    const int s = p - begin;
    const int left = end - p;
    const __mmask8 valid = left >= 8 ? 0xFF : static_cast<__mmask8>((1u << left) - 1u);
    const Mask8 in_range{valid};
    const __m256i i = _mm256_maskz_loadu_epi32(valid, b.pair_i + p);
    const __m256i j = _mm256_maskz_loadu_epi32(valid, b.pair_j + p);
    // The pairs come row by row (i ascending), so the eight i of a vector are mostly a few
    // neighbouring disks: then one load of i0 .. i0 + span and a permutation give what a
    // gather would, at a fraction of its cost.
    const int i0 = b.pair_i[p];
    const int span = b.pair_i[p + (left >= 8 ? 7 : left - 1)] - i0;
    const bool near = span < 8;
    const __mmask8 near_lanes = static_cast<__mmask8>((2u << (near ? span : 0)) - 1u);
    const __m512i from_i0 = _mm512_cvtepi32_epi64(_mm256_sub_epi32(i, _mm256_set1_epi32(i0)));
    const auto at_i = [&](const double* a) {
      return near ? Double8(
                        _mm512_permutexvar_pd(from_i0, _mm512_maskz_loadu_pd(near_lanes, a + i0)))
                  : gather(a, i);
    };
    Double8 dx = gather(b.x, j) - at_i(b.x);
    Double8 dy = gather(b.y, j) - at_i(b.y);
    if constexpr (Periodic) {
      dx = minimum_image(dx, l1, half_l1);
      dy = minimum_image(dy, l2, half_l2);
    }
    const Double8 ri = at_i(b.radius), rj = gather(b.radius, j);
    const Double8 reach = ri + rj;
    const Mask8 closed =
        Mask8{_mm512_cmp_pd_mask((dx * dx + dy * dy).v, (reach * reach).v, _CMP_NGE_UQ)} & in_range;
    // Also for the vectors of open pairs: the sweep needs "closed before" of every pair, and its
    // scalar read of f_n stalled on the miss (16 % of the sweep at N = 22400, perf annotate).
    const Double8 f_n_before = _mm512_maskz_loadu_pd(valid, b.f_n + p);
    const Mask8 closed_before = (f_n_before > 0.0) & in_range;
    _mm_storel_epi64(reinterpret_cast<__m128i*>(b.closed + s),
                     _mm_or_si128(_mm_maskz_set1_epi8(closed.m, closed_now),
                                  _mm_maskz_set1_epi8(closed_before.m, was_closed)));
    // Compressed in a register and stored whole (the scratch is padded): a compressing store
    // to memory is far slower on Intel cores.
    const __mmask8 touched_lanes = closed.m | closed_before.m;
    _mm256_storeu_si256(
        reinterpret_cast<__m256i*>(b.touched + touched),
        _mm256_maskz_compress_epi32(touched_lanes, _mm256_add_epi32(lane, _mm256_set1_epi32(s))));
    touched += __builtin_popcount(touched_lanes);
    if (closed.m == 0) continue;
    const auto keep_state = [&](Double8 delta_t, Double8 f_n, Double8 nx, Double8 ny) {
      _mm512_mask_storeu_pd(b.delta_t + p, closed.m, delta_t.v);
      _mm512_mask_storeu_pd(b.f_n + p, closed.m, f_n.v);
      _mm512_mask_storeu_pd(b.nx + p, closed.m, nx.v);
      _mm512_mask_storeu_pd(b.ny + p, closed.m, ny.v);
      _mm512_mask_storeu_pd(b.lx + p, closed.m, dx.v);
      _mm512_mask_storeu_pd(b.ly + p, closed.m, dy.v);
    };
    const ClosedPair<Double8> c = closed_pair_law<Periodic>(
        k, dx, dy, ri, rj, at_i(b.vx), at_i(b.vy), at_i(b.omega), gather(b.vx, j), gather(b.vy, j),
        gather(b.omega, j), at_i(b.vvx), at_i(b.vvy), gather(b.vvx, j), gather(b.vvy, j),
        Double8(_mm512_maskz_loadu_pd(valid, b.alpha + p)),
        Double8(_mm512_maskz_loadu_pd(valid, b.delta_t + p)), f_n_before > 0.0, keep_state);
    _mm512_storeu_pd(b.fx + s, c.fx.v);
    _mm512_storeu_pd(b.fy + s, c.fy.v);
    _mm512_storeu_pd(b.fvx + s, c.fvx.v);
    _mm512_storeu_pd(b.fvy + s, c.fvy.v);
    _mm512_storeu_pd(b.torque_i + s, c.torque_i.v);
    _mm512_storeu_pd(b.torque_j + s, c.torque_j.v);
  }
  return touched;
}

}  // namespace

int pair_law(const PairBlock& b, const PairLawConstants& k, bool periodic, double l1, double l2,
             int begin, int end) {
  return periodic ? pair_law<true>(b, k, l1, l2, begin, end)
                  : pair_law<false>(b, k, l1, l2, begin, end);
}

}  // namespace granstab::dynamic::simd
#else
namespace granstab::dynamic::simd {
int pair_law(const PairBlock&, const PairLawConstants&, bool, double, double, int, int) {
  return 0;
}
}  // namespace granstab::dynamic::simd
#endif

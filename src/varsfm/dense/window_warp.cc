#include "varsfm/dense/window_warp.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define VARSFM_AVX2_WARP 1
#endif

namespace varsfm {
namespace {

// The lanes' partial sums added up pairwise, (l0 + l4) + (l2 + l6) and (l1 + l5) + (l3 + l7),
// the same in every path: a tree is a shorter chain of dependent additions than a row.
[[gnu::always_inline]] inline float SumLanes(const float (&lane)[kWarpLanes]) {
  const float a0 = lane[0] + lane[4], a1 = lane[1] + lane[5];
  const float a2 = lane[2] + lane[6], a3 = lane[3] + lane[7];
  return (a0 + a2) + (a1 + a3);
}

[[gnu::always_inline]] inline void SumLanes(const float (&s)[kWarpLanes],
                                            const float (&ss)[kWarpLanes],
                                            const float (&rs)[kWarpLanes], WarpSums* sums) {
  *sums = {SumLanes(s), SumLanes(ss), SumLanes(rs)};
}

// The mask of the lanes of samples [i, i + lanes) that hold samples, for movemask.
inline int LiveLanes(int i, int count, int lanes) { return (1 << std::min(lanes, count - i)) - 1; }

// Sample i's warped intensity into *v, with each lane's operations of the vector paths in their
// order (SampleBilinear's). False when it falls behind the source.
[[gnu::always_inline]] inline bool WarpOne(const WarpWindow& w, const WarpSource& src,
                                           const float* H, const float* h0, int i, float* v) {
  const float hx = (h0[0] + H[0] * w.dx[i]) + H[3] * w.dy[i];
  const float hy = (h0[1] + H[1] * w.dx[i]) + H[4] * w.dy[i];
  const float hz = (h0[2] + H[2] * w.dx[i]) + H[5] * w.dy[i];
  if (hz <= 1e-6f) return false;
  *v = SampleBilinear(src, hx / hz, hy / hz);
  return true;
}

// Samples [first, w.count) one at a time, each into its lane's partial sums (sample i in lane
// i % kWarpLanes, as a vector step would put it), then the lanes summed: the whole window on the
// portable path, the samples after the whole vector groups on the others. False when a sample
// falls behind the source.
[[gnu::always_inline]] inline bool FinishOneAtATime(const WarpWindow& w, const WarpSource& src,
                                                    const float* H, const float* h0, int first,
                                                    float (&s)[kWarpLanes], float (&ss)[kWarpLanes],
                                                    float (&rs)[kWarpLanes], WarpSums* sums) {
  for (int i = first; i < w.count; ++i) {
    float v;
    if (!WarpOne(w, src, H, h0, i, &v)) return false;
    const int l = i % kWarpLanes;
    const float wv = w.weight[i] * v;
    s[l] += wv, ss[l] += wv * v, rs[l] += wv * w.value[i];
  }
  SumLanes(s, ss, rs, sums);
  return true;
}

#if defined(__SSE2__)
// Two adjacent floats (p[0], p[1]) in the low lanes of a register, by one 64-bit load.
inline __m128 Pair(const float* p) {
  return _mm_castpd_ps(_mm_load_sd(reinterpret_cast<const double*>(p)));
}

// Each lane's bilinear value from its 2 x 2 neighbourhood, given as pair registers of the top
// (t, u) and bottom (b, c) rows whose even lanes are the left pixels and odd lanes the right
// ones, and its fractions fx, fy: SampleBilinear's operations, in its order. For both register
// widths: GCC's vector operators on __m128 and __m256 are the instructions its _mm*_add_ps,
// _sub_ps and _mul_ps intrinsics stand for, and neither kernel's target has FMA to contract them.
// (Registers by reference: a 256-bit value passed by value outside an AVX target changes the
// calling convention, and GCC warns although it is always inlined.)
template <typename V, typename EvenOdd>
[[gnu::always_inline]] inline void BlendPairs(const V& t, const V& u, const V& b, const V& c,
                                              const V& fx, const V& fy, EvenOdd even_odd, V* v) {
  V a00, a01, a10, a11;
  even_odd(t, u, &a00, &a01);
  even_odd(b, c, &a10, &a11);
  const V top = a00 + fx * (a01 - a00);
  const V bottom = a10 + fx * (a11 - a10);
  *v = top * (1.0f - fy) + bottom * fy;
}

// Samples [i, i + 4): their warped intensities into *v. False when one of them that holds a
// sample falls behind the source.
[[gnu::always_inline]] inline bool Warp4(const WarpWindow& w, const WarpSource& src, const float* H,
                                         const float* h0, int i, __m128* v) {
  const __m128 zero = _mm_setzero_ps(), half = _mm_set1_ps(0.5f);
  const __m128 dx = _mm_load_ps(w.dx + i), dy = _mm_load_ps(w.dy + i);
  // h = (h0 + H.col(0) dx) + H.col(1) dy.
  const __m128 hx = _mm_add_ps(_mm_add_ps(_mm_set1_ps(h0[0]), _mm_mul_ps(_mm_set1_ps(H[0]), dx)),
                               _mm_mul_ps(_mm_set1_ps(H[3]), dy));
  const __m128 hy = _mm_add_ps(_mm_add_ps(_mm_set1_ps(h0[1]), _mm_mul_ps(_mm_set1_ps(H[1]), dx)),
                               _mm_mul_ps(_mm_set1_ps(H[4]), dy));
  const __m128 hz = _mm_add_ps(_mm_add_ps(_mm_set1_ps(h0[2]), _mm_mul_ps(_mm_set1_ps(H[2]), dx)),
                               _mm_mul_ps(_mm_set1_ps(H[5]), dy));
  if (_mm_movemask_ps(_mm_cmple_ps(hz, _mm_set1_ps(1e-6f))) & LiveLanes(i, w.count, 4))
    return false;
  // The centre-based coordinates clamped to the border, then bilinear.
  const __m128 max_x = _mm_set1_ps(src.width - 1.001f), max_y = _mm_set1_ps(src.height - 1.001f);
  const __m128 x = _mm_min_ps(_mm_max_ps(_mm_sub_ps(_mm_div_ps(hx, hz), half), zero), max_x);
  const __m128 y = _mm_min_ps(_mm_max_ps(_mm_sub_ps(_mm_div_ps(hy, hz), half), zero), max_y);
  const __m128i x0 = _mm_cvttps_epi32(x), y0 = _mm_cvttps_epi32(y);
  const __m128 fx = _mm_sub_ps(x, _mm_cvtepi32_ps(x0));
  const __m128 fy = _mm_sub_ps(y, _mm_cvtepi32_ps(y0));
  alignas(16) int32_t xs[4], ys[4];
  _mm_store_si128(reinterpret_cast<__m128i*>(xs), x0);
  _mm_store_si128(reinterpret_cast<__m128i*>(ys), y0);
  // Each lane's 2 x 2 neighbourhood as (p00, p01) and (p10, p11) pairs, gathered into
  // registers directly (scalar stores read back as a vector would stall store forwarding).
  const size_t w1 = static_cast<size_t>(src.width);
  const float* r[4];
  for (int l = 0; l < 4; ++l) r[l] = src.pixels + static_cast<size_t>(ys[l]) * w1 + xs[l];
  // t01 = (left 0, right 0, left 1, right 1): the even lanes are the left pixels.
  const __m128 t01 = _mm_movelh_ps(Pair(r[0]), Pair(r[1]));
  const __m128 t23 = _mm_movelh_ps(Pair(r[2]), Pair(r[3]));
  const __m128 b01 = _mm_movelh_ps(Pair(r[0] + w1), Pair(r[1] + w1));
  const __m128 b23 = _mm_movelh_ps(Pair(r[2] + w1), Pair(r[3] + w1));
  const auto even_odd = [](const __m128& p, const __m128& q, __m128* even, __m128* odd) {
    *even = _mm_shuffle_ps(p, q, _MM_SHUFFLE(2, 0, 2, 0));
    *odd = _mm_shuffle_ps(p, q, _MM_SHUFFLE(3, 1, 3, 1));
  };
  BlendPairs(t01, t23, b01, b23, fx, fy, even_odd, v);
  return true;
}

// Adds samples [i, i + 4)'s terms, their intensities v, to the partial sums of lanes 0-3 or 4-7.
[[gnu::always_inline]] inline void Accumulate4(const WarpWindow& w, int i, __m128 v, __m128* s,
                                               __m128* ss, __m128* rs) {
  const __m128 wv = _mm_mul_ps(_mm_load_ps(w.weight + i), v);
  *s = _mm_add_ps(*s, wv);
  *ss = _mm_add_ps(*ss, _mm_mul_ps(wv, v));
  *rs = _mm_add_ps(*rs, _mm_mul_ps(wv, _mm_load_ps(w.value + i)));
}

bool WarpAndSumSse2(const WarpWindow& w, const WarpSource& src, const float* H, const float* h0,
                    WarpSums* sums) {
  // Lanes 0-3 and 4-7 of the eight-lane partial sums.
  __m128 acc_s[2] = {}, acc_ss[2] = {}, acc_rs[2] = {};
  int i = 0;
  for (; w.count - i >= 4; i += 4) {
    __m128 v;
    if (!Warp4(w, src, H, h0, i, &v)) return false;
    const int k = (i / 4) % 2;
    Accumulate4(w, i, v, &acc_s[k], &acc_ss[k], &acc_rs[k]);
  }
  float s[kWarpLanes], ss[kWarpLanes], rs[kWarpLanes];
  for (int k = 0; k < 2; ++k) {
    _mm_storeu_ps(s + 4 * k, acc_s[k]);
    _mm_storeu_ps(ss + 4 * k, acc_ss[k]);
    _mm_storeu_ps(rs + 4 * k, acc_rs[k]);
  }
  // The samples after whole groups of four one at a time, as in the AVX2 path.
  return FinishOneAtATime(w, src, H, h0, i, s, ss, rs, sums);
}
#endif

// The portable path, one sample at a time.
bool WarpAndSumPlain(const WarpWindow& w, const WarpSource& src, const float* H, const float* h0,
                     WarpSums* sums) {
  float s[kWarpLanes] = {}, ss[kWarpLanes] = {}, rs[kWarpLanes] = {};
  return FinishOneAtATime(w, src, H, h0, 0, s, ss, rs, sums);
}

#if defined(VARSFM_AVX2_WARP)
#define VARSFM_AVX2_TARGET __attribute__((target("avx2")))

// Four adjacent pairs (p[0], p[1]) of lanes a, b (low half) and c, d (high half).
VARSFM_AVX2_TARGET inline __m256 Pairs(const float* a, const float* b, const float* c,
                                       const float* d) {
  return _mm256_set_m128(_mm_movelh_ps(Pair(c), Pair(d)), _mm_movelh_ps(Pair(a), Pair(b)));
}

// As WarpAndSumSse2, eight lanes in one register. The pixels are loaded in pairs rather than by
// _mm256_i32gather_ps, which was slower on the AMD EPYC the benchmarks run on.
VARSFM_AVX2_TARGET bool WarpAndSumAvx2(const WarpWindow& w, const WarpSource& src, const float* H,
                                       const float* h0, WarpSums* sums) {
  const __m256 h0x = _mm256_set1_ps(h0[0]), h0y = _mm256_set1_ps(h0[1]);
  const __m256 h0z = _mm256_set1_ps(h0[2]);
  const __m256 ax = _mm256_set1_ps(H[0]), ay = _mm256_set1_ps(H[1]), az = _mm256_set1_ps(H[2]);
  const __m256 bx = _mm256_set1_ps(H[3]), by = _mm256_set1_ps(H[4]), bz = _mm256_set1_ps(H[5]);
  const __m256 min_z = _mm256_set1_ps(1e-6f), half = _mm256_set1_ps(0.5f);
  const __m256 zero = _mm256_setzero_ps();
  const __m256 max_x = _mm256_set1_ps(src.width - 1.001f);
  const __m256 max_y = _mm256_set1_ps(src.height - 1.001f);
  const size_t w1 = static_cast<size_t>(src.width);
  __m256 acc_s = zero, acc_ss = zero, acc_rs = zero;
  int i = 0;
  for (; w.count - i > 4; i += kWarpLanes) {
    const __m256 dx = _mm256_load_ps(w.dx + i), dy = _mm256_load_ps(w.dy + i);
    const __m256 hx =
        _mm256_add_ps(_mm256_add_ps(h0x, _mm256_mul_ps(ax, dx)), _mm256_mul_ps(bx, dy));
    const __m256 hy =
        _mm256_add_ps(_mm256_add_ps(h0y, _mm256_mul_ps(ay, dx)), _mm256_mul_ps(by, dy));
    const __m256 hz =
        _mm256_add_ps(_mm256_add_ps(h0z, _mm256_mul_ps(az, dx)), _mm256_mul_ps(bz, dy));
    if (_mm256_movemask_ps(_mm256_cmp_ps(hz, min_z, _CMP_LE_OQ)) &
        LiveLanes(i, w.count, kWarpLanes))
      return false;
    const __m256 x =
        _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(_mm256_div_ps(hx, hz), half), zero), max_x);
    const __m256 y =
        _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(_mm256_div_ps(hy, hz), half), zero), max_y);
    const __m256i x0 = _mm256_cvttps_epi32(x), y0 = _mm256_cvttps_epi32(y);
    const __m256 fx = _mm256_sub_ps(x, _mm256_cvtepi32_ps(x0));
    const __m256 fy = _mm256_sub_ps(y, _mm256_cvtepi32_ps(y0));
    alignas(32) int32_t xs[kWarpLanes], ys[kWarpLanes];
    _mm256_store_si256(reinterpret_cast<__m256i*>(xs), x0);
    _mm256_store_si256(reinterpret_cast<__m256i*>(ys), y0);
    const float* r[kWarpLanes];
    for (int l = 0; l < kWarpLanes; ++l)
      r[l] = src.pixels + static_cast<size_t>(ys[l]) * w1 + xs[l];
    // Within each 128-bit half the shuffles take the even (left) and odd (right) pixels of two
    // pair registers: lanes 0, 1, 4, 5 and 2, 3, 6, 7 hold samples in order.
    const __m256 tA = Pairs(r[0], r[1], r[4], r[5]), tB = Pairs(r[2], r[3], r[6], r[7]);
    const __m256 bA = Pairs(r[0] + w1, r[1] + w1, r[4] + w1, r[5] + w1);
    const __m256 bB = Pairs(r[2] + w1, r[3] + w1, r[6] + w1, r[7] + w1);
    const auto even_odd = [](const __m256& p, const __m256& q, __m256* even, __m256* odd)
                              VARSFM_AVX2_TARGET {
                                *even = _mm256_shuffle_ps(p, q, _MM_SHUFFLE(2, 0, 2, 0));
                                *odd = _mm256_shuffle_ps(p, q, _MM_SHUFFLE(3, 1, 3, 1));
                              };
    __m256 v;
    BlendPairs(tA, tB, bA, bB, fx, fy, even_odd, &v);
    const __m256 wv = _mm256_mul_ps(_mm256_load_ps(w.weight + i), v);
    acc_s = _mm256_add_ps(acc_s, wv);
    acc_ss = _mm256_add_ps(acc_ss, _mm256_mul_ps(wv, v));
    acc_rs = _mm256_add_ps(acc_rs, _mm256_mul_ps(wv, _mm256_load_ps(w.value + i)));
  }
  float s[kWarpLanes], ss[kWarpLanes], rs[kWarpLanes];
  _mm256_storeu_ps(s, acc_s);
  _mm256_storeu_ps(ss, acc_ss);
  _mm256_storeu_ps(rs, acc_rs);
  // At most four samples left (a (2k + 1)^2 window leaves one: odd squares are 1 modulo 8), one
  // at a time into lanes 0-3 rather than by a vector step, whose set-up and split accumulators
  // cost far more than one sample (bench/results/2026-12-07-s41-warp-tail.md). The padded lanes
  // a vector step would have added are 0 + 0 = 0, and the sums are never -0 (the weights and
  // intensities are not negative), so the bits are the same.
  return FinishOneAtATime(w, src, H, h0, i, s, ss, rs, sums);
}

bool CpuHasAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

const bool kCpuHasAvx2 = CpuHasAvx2();
#endif

}  // namespace

bool WarpKernelAvailable(WarpKernel kernel) {
  switch (kernel) {
    case WarpKernel::kBest:
    case WarpKernel::kPlain:
      return true;
    case WarpKernel::kSse2:
#if defined(__SSE2__)
      return true;
#else
      return false;
#endif
    case WarpKernel::kAvx2:
#if defined(VARSFM_AVX2_WARP)
      return kCpuHasAvx2;
#else
      return false;
#endif
  }
  return false;
}

bool WarpAndSum(const WarpWindow& window, const WarpSource& source, const float* H, const float* h0,
                WarpSums* sums, WarpKernel kernel) {
  if (kernel == WarpKernel::kPlain) return WarpAndSumPlain(window, source, H, h0, sums);
#if defined(VARSFM_AVX2_WARP)
  if (kCpuHasAvx2 && kernel != WarpKernel::kSse2)
    return WarpAndSumAvx2(window, source, H, h0, sums);
#endif
#if defined(__SSE2__)
  return WarpAndSumSse2(window, source, H, h0, sums);
#else
  return WarpAndSumPlain(window, source, H, h0, sums);
#endif
}

}  // namespace varsfm

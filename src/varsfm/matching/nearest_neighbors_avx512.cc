// The AVX-512 VNNI kernel. Only its functions are compiled for AVX-512 (target attributes, no
// global flags), so the library still runs on any x86-64; descriptor_matcher.cc calls it only
// after CpuHasAvx512Vnni().
//
// vpdpbusd multiplies unsigned by signed bytes, so B is stored as (b - 128) and the exact dot
// product is recovered as sum(a * (b - 128)) + 128 * sum(a). Each 8-row x 32-column tile of
// dot products is folded at once into the running best/second-best of its rows (per-lane, then
// reduced across lanes at the end of the row) and of its columns.
#include "varsfm/matching/nearest_neighbors.h"

#if defined(__x86_64__) && defined(__GNUC__)
// GCC 12 warns about the deliberately undefined source operand inside the broadcast/convert
// intrinsics of its own headers (a known false positive).
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <immintrin.h>

#include <algorithm>
#include <cstring>

namespace varsfm::internal {
namespace {

constexpr int kDim = 128;
constexpr int kRows = 8;   // rows of A per tile
constexpr int kCols = 32;  // columns (rows of B) per tile: two zmm of int32
constexpr float kNoScore = -1.0f;

#define VARSFM_AVX512_TARGET __attribute__((target("avx512f,avx512bw,avx512vnni")))

// Collapses one row's 16 lanes into best (smallest index among ties) and second best.
VARSFM_AVX512_TARGET void ReduceLanes(__m512 m1v, __m512 m2v, __m512i idxv, int* best,
                                      float* best_score, float* second_score) {
  alignas(64) float m1[16], m2[16];
  alignas(64) int idx[16];
  _mm512_store_ps(m1, m1v);
  _mm512_store_ps(m2, m2v);
  _mm512_store_si512(idx, idxv);
  int lane = 0;
  for (int l = 1; l < 16; ++l) {
    if (m1[l] > m1[lane] || (m1[l] == m1[lane] && idx[l] < idx[lane])) lane = l;
  }
  float second = m2[lane];
  for (int l = 0; l < 16; ++l) {
    if (l != lane) second = std::max(second, m1[l]);
  }
  *best = m1[lane] > kNoScore ? idx[lane] : -1;
  *best_score = m1[lane];
  *second_score = second;
}

}  // namespace

VARSFM_AVX512_TARGET void FindNearestNeighborsAvx512Vnni(const PreparedDescriptors& a,
                                                         const PreparedDescriptors& b,
                                                         NearestNeighbors* nn) {
  const int n1 = a.num, n2 = b.num;
  nn->row_best.assign(n1, -1);
  nn->row_best_score.assign(n1, kNoScore);
  nn->row_second_score.assign(n1, kNoScore);
  if (n1 == 0 || n2 == 0) {
    nn->col_best.assign(n2, -1);
    nn->col_best_score.assign(n2, kNoScore);
    nn->col_second_score.assign(n2, kNoScore);
    return;
  }
  const int tiles = (n2 + kCols - 1) / kCols;
  const int n2_padded = tiles * kCols;
  // Column state over padded columns (padding is never read back).
  std::vector<float> col_m1(n2_padded, kNoScore), col_m2(n2_padded, kNoScore);
  std::vector<int> col_idx(n2_padded, -1);
  const __m512i lane_index =
      _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const __m512 invalid = _mm512_set1_ps(2 * kNoScore);

  for (int i0 = 0; i0 < n1; i0 += kRows) {
    const int rows = std::min(kRows, n1 - i0);
    __m512 rm1[kRows], rm2[kRows], inv_na[kRows];
    __m512i ridx[kRows], correction[kRows];
    for (int r = 0; r < kRows; ++r) {
      rm1[r] = _mm512_set1_ps(kNoScore);
      rm2[r] = _mm512_set1_ps(kNoScore);
      ridx[r] = _mm512_set1_epi32(-1);
      correction[r] = _mm512_set1_epi32(128 * a.row_sum[i0 + r]);
      inv_na[r] = _mm512_set1_ps(a.inv_norm[i0 + r]);
    }
    const uint8_t* arow = &a.rows[static_cast<size_t>(i0) * kDim];

    for (int t = 0; t < tiles; ++t) {
      __m512i acc[kRows][2];
      for (int r = 0; r < kRows; ++r) acc[r][0] = acc[r][1] = _mm512_setzero_si512();
      const int8_t* bp = &b.packed[static_cast<size_t>(t) * kCols * kDim];
      for (int g = 0; g < kDim / 4; ++g) {
        const __m512i b0 = _mm512_loadu_si512(bp + g * 128);
        const __m512i b1 = _mm512_loadu_si512(bp + g * 128 + 64);
        for (int r = 0; r < kRows; ++r) {
          int32_t four;
          std::memcpy(&four, arow + r * kDim + 4 * g, 4);
          const __m512i av = _mm512_set1_epi32(four);
          acc[r][0] = _mm512_dpbusd_epi32(acc[r][0], av, b0);
          acc[r][1] = _mm512_dpbusd_epi32(acc[r][1], av, b1);
        }
      }
      for (int h = 0; h < 2; ++h) {
        const int j0 = t * kCols + h * 16;
        const __m512i jv = _mm512_add_epi32(_mm512_set1_epi32(j0), lane_index);
        const __mmask16 valid = _mm512_cmplt_epi32_mask(jv, _mm512_set1_epi32(n2));
        const __m512 inv_nb = _mm512_loadu_ps(&b.inv_norm[j0]);
        __m512 cm1 = _mm512_loadu_ps(&col_m1[j0]);
        __m512 cm2 = _mm512_loadu_ps(&col_m2[j0]);
        __m512i cidx = _mm512_loadu_si512(&col_idx[j0]);
        for (int r = 0; r < rows; ++r) {
          const __m512i dot = _mm512_add_epi32(acc[r][h], correction[r]);
          // Same float operations, same order, as the generic kernel: (dot * inv_nb) * inv_na.
          __m512 s = _mm512_mul_ps(_mm512_mul_ps(_mm512_cvtepi32_ps(dot), inv_nb), inv_na[r]);
          s = _mm512_mask_blend_ps(valid, invalid, s);
          const __mmask16 row_gt = _mm512_cmp_ps_mask(s, rm1[r], _CMP_GT_OQ);
          rm2[r] = _mm512_max_ps(rm2[r], _mm512_min_ps(rm1[r], s));
          rm1[r] = _mm512_max_ps(rm1[r], s);
          ridx[r] = _mm512_mask_mov_epi32(ridx[r], row_gt, jv);
          const __mmask16 col_gt = _mm512_cmp_ps_mask(s, cm1, _CMP_GT_OQ);
          cm2 = _mm512_max_ps(cm2, _mm512_min_ps(cm1, s));
          cm1 = _mm512_max_ps(cm1, s);
          cidx = _mm512_mask_mov_epi32(cidx, col_gt, _mm512_set1_epi32(i0 + r));
        }
        _mm512_storeu_ps(&col_m1[j0], cm1);
        _mm512_storeu_ps(&col_m2[j0], cm2);
        _mm512_storeu_si512(&col_idx[j0], cidx);
      }
    }
    for (int r = 0; r < rows; ++r) {
      ReduceLanes(rm1[r], rm2[r], ridx[r], &nn->row_best[i0 + r], &nn->row_best_score[i0 + r],
                  &nn->row_second_score[i0 + r]);
    }
  }
  nn->col_best.assign(col_idx.begin(), col_idx.begin() + n2);
  nn->col_best_score.assign(col_m1.begin(), col_m1.begin() + n2);
  nn->col_second_score.assign(col_m2.begin(), col_m2.begin() + n2);
}

}  // namespace varsfm::internal

#else  // not x86-64 GCC/Clang: CpuHasAvx512Vnni() is false, so this is never called.

#include "varsfm/util/error.h"

namespace varsfm::internal {
void FindNearestNeighborsAvx512Vnni(const PreparedDescriptors&, const PreparedDescriptors&,
                                    NearestNeighbors*) {
  Fail("the AVX-512 VNNI matching kernel is not available on this platform");
}
}  // namespace varsfm::internal

#endif

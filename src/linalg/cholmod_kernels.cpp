#include "cholmod_kernels.hpp"

namespace jamsim::linalg::factor_kernels {

// The sweep's kernels for columns whose rows are consecutive places in the workspace (the
// dense separators at the top of the tree, where every change's path ends and most of the
// entry updates are): whole blocks of rows, `kVecs` vectors of V per column; they return how
// many rows they did (the caller does the rest entry by entry). Element-wise vector
// arithmetic without contraction into FMAs, so every vector width gives the same bits as
// scalar code: the width is only a matter of speed. Each entry's chain of operations runs
// through all the column's changes in turn, so a block needs enough independent rows to
// hide that chain's latency: blocks of 16 rows (8 SSE2 pairs, 4 AVX2 quads or 2 AVX-512
// octets per column; for two columns with SSE2 only 8, the most its 16 registers hold), then
// a tier of 8 rows.
// (Loads and stores by memcpy written out in the kernels: a helper returning a 32-byte
// vector would be a default-target function with an AVX ABI.)
#define JAMSIM_LOAD(V, dst, at) std::memcpy(&(dst), (at), sizeof(V))
#define JAMSIM_STORE(at, src) std::memcpy((at), &(src), sizeof(src))

/// One column: for each change s in order, w_r ← w_r − p l_r, then l_r ← l_r + β w_r.
template <class V, int kVecs>
[[gnu::always_inline]] inline int consecutive_blocks(ColumnChanges c, double* l, int row0, int len, int count) {
    constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
    int k = 0;
    for (; k + kWidth * kVecs <= len; k += kWidth * kVecs) {
        V v[kVecs];
        for (int u = 0; u < kVecs; ++u) JAMSIM_LOAD(V, v[u], l + k + kWidth * u);
        for (int s = 0; s < count; ++s) {
            double* wr = c.w[s] + row0 + k;
            const double p = c.p[s], beta = c.beta[s];
            for (int u = 0; u < kVecs; ++u) {
                V wk;
                JAMSIM_LOAD(V, wk, wr + kWidth * u);
                wk = wk - p * v[u];
                JAMSIM_STORE(wr + kWidth * u, wk);
                v[u] += beta * wk;
            }
        }
        for (int u = 0; u < kVecs; ++u) JAMSIM_STORE(l + k + kWidth * u, v[u]);
    }
    return k;
}

/// Two columns of a pair over the same rows and changes (the second column's coefficients
/// in `second`, its workspaces those of `first`): per entry and change, the first column's
/// step before the second's, as column after column.
template <class V, int kVecs>
[[gnu::always_inline]] inline int consecutive2_blocks(ColumnChanges first, ColumnChanges second, double* l1, double* l2,
                                                      int row0, int len, int count) {
    constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(double));
    int k = 0;
    for (; k + kWidth * kVecs <= len; k += kWidth * kVecs) {
        V v1[kVecs], v2[kVecs];
        for (int u = 0; u < kVecs; ++u) {
            JAMSIM_LOAD(V, v1[u], l1 + k + kWidth * u);
            JAMSIM_LOAD(V, v2[u], l2 + k + kWidth * u);
        }
        for (int s = 0; s < count; ++s) {
            double* wr = first.w[s] + row0 + k;
            const double p1 = first.p[s], beta1 = first.beta[s], p2 = second.p[s], beta2 = second.beta[s];
            for (int u = 0; u < kVecs; ++u) {
                V wk;
                JAMSIM_LOAD(V, wk, wr + kWidth * u);
                wk = wk - p1 * v1[u];
                v1[u] += beta1 * wk;
                wk = wk - p2 * v2[u];
                JAMSIM_STORE(wr + kWidth * u, wk);
                v2[u] += beta2 * wk;
            }
        }
        for (int u = 0; u < kVecs; ++u) {
            JAMSIM_STORE(l1 + k + kWidth * u, v1[u]);
            JAMSIM_STORE(l2 + k + kWidth * u, v2[u]);
        }
    }
    return k;
}

#undef JAMSIM_LOAD
#undef JAMSIM_STORE

/// Blocks of kVecs vectors (16 rows), then a tier of half as many (8 rows): runs of 8 or more
/// rows take these kernels (see by_runs).
template <class V, int kVecs>
[[gnu::always_inline]] inline int tiered_blocks(ColumnChanges c, double* l, int row0, int len, int count) {
    const int k = consecutive_blocks<V, kVecs>(c, l, row0, len, count);
    return k + consecutive_blocks<V, kVecs / 2>(c, l + k, row0 + k, len - k, count);
}
template <class V, int kVecs>
[[gnu::always_inline]] inline int tiered_blocks2(ColumnChanges a, ColumnChanges b, double* l1, double* l2, int row0,
                                                 int len, int count) {
    const int k = consecutive2_blocks<V, kVecs>(a, b, l1, l2, row0, len, count);
    return k + consecutive2_blocks<V, kVecs / 2>(a, b, l1 + k, l2 + k, row0 + k, len - k, count);
}

int consecutive_sse2(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Pair, 8>(c, l, row0, len, count);
}
int consecutive2_sse2(ColumnChanges a, ColumnChanges b, double* l1, double* l2, int row0, int len, int count) {
    return consecutive2_blocks<Pair, 4>(a, b, l1, l2, row0, len, count);  // 8 rows already
}

#if defined(__x86_64__) && defined(__GNUC__)
#define JAMSIM_HAVE_WIDE_KERNELS 1
using Quad = double __attribute__((vector_size(32)));
using Oct = double __attribute__((vector_size(64)));  // AVX-512's 32 registers hold 2 per column of a pair
__attribute__((target("avx2"))) int consecutive_avx2(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Quad, 4>(c, l, row0, len, count);
}
__attribute__((target("avx2"))) int consecutive2_avx2(ColumnChanges a, ColumnChanges b, double* l1, double* l2,
                                                      int row0, int len, int count) {
    return tiered_blocks2<Quad, 4>(a, b, l1, l2, row0, len, count);
}
__attribute__((target("avx512f"))) int consecutive_avx512(ColumnChanges c, double* l, int row0, int len, int count) {
    return tiered_blocks<Oct, 2>(c, l, row0, len, count);
}
__attribute__((target("avx512f"))) int consecutive2_avx512(ColumnChanges a, ColumnChanges b, double* l1, double* l2,
                                                           int row0, int len, int count) {
    return tiered_blocks2<Oct, 2>(a, b, l1, l2, row0, len, count);
}
#endif

WideKernels choose_kernels(CholmodUpdatedFactor::Vectors vectors) {
    using Vectors = CholmodUpdatedFactor::Vectors;
    WideKernels k;
#ifdef JAMSIM_HAVE_WIDE_KERNELS
    __builtin_cpu_init();
    if (vectors == Vectors::best && __builtin_cpu_supports("avx512f"))
        return {consecutive_avx512, consecutive2_avx512, "avx512f"};
    if (vectors != Vectors::sse2 && __builtin_cpu_supports("avx2"))
        return {consecutive_avx2, consecutive2_avx2, "avx2"};
#else
    (void)vectors;
#endif
    return k;
}

}  // namespace jamsim::linalg::factor_kernels

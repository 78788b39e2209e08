#pragma once
// The consecutive-row kernels of the updated CD0 factor's sweep (cholmod_factor.hpp): the
// entry updates of a column whose rows are consecutive places in the sweep's workspace, in
// SIMD vectors of the widest kind the processor has. Internal to src/linalg.
#include <cstring>

#include "cholmod_factor.hpp"

namespace jamsim::linalg::factor_kernels {

/// Two doubles as one SIMD register (GCC/Clang vector extension; element-wise, so the
/// results are bitwise those of scalar code on every target).
using Pair = double __attribute__((vector_size(16)));
inline Pair load(const double* at) {
    Pair v;
    std::memcpy(&v, at, sizeof v);
    return v;
}
inline void store(double* at, Pair v) { std::memcpy(at, &v, sizeof v); }

/// The coefficients of a column's changes in the sweep: for change s, p[s] (the column's
/// workspace entry), beta[s] and w[s] (its workspace, indexed by place).
struct ColumnChanges {
    const double* p;
    const double* beta;
    double* const* w;
};

/// The kernels return how many rows they did from the start (whole blocks; the caller does
/// the rest entry by entry).
using ConsecutiveKernel = int (*)(ColumnChanges, double*, int, int, int);
using Consecutive2Kernel = int (*)(ColumnChanges, ColumnChanges, double*, double*, int, int, int);

int consecutive_sse2(ColumnChanges c, double* l, int row0, int len, int count);
int consecutive2_sse2(ColumnChanges a, ColumnChanges b, double* l1, double* l2, int row0, int len, int count);

/// The consecutive-row kernels of the widest vectors that `vectors` allows and the
/// processor has (the operating system's support of the registers included).
struct WideKernels {
    ConsecutiveKernel one = consecutive_sse2;
    Consecutive2Kernel two = consecutive2_sse2;
    const char* name = "sse2";
};
WideKernels choose_kernels(CholmodUpdatedFactor::Vectors vectors);

}  // namespace jamsim::linalg::factor_kernels

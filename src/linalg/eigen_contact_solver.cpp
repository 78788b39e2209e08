#include "jamsim/linalg/eigen_contact_solver.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "updated_factor_solve.hpp"

namespace jamsim::linalg {

namespace {

/// A copy of Eigen's LDLᵀ factor (P A Pᵀ = L D Lᵀ, L unit lower, CSC with sorted rows) that
/// can be modified in place: a contact (i, j) forming adds (e_i − e_j)(e_i − e_j)ᵀ to A,
/// breaking subtracts it. Rank-one update/downdate by method C1 of Gill, Golub, Murray and
/// Saunders (1974), restricted to the elimination-tree paths from P i and P j (Davis and
/// Hager 1999). The symbolic pattern was analysed for every candidate pair, so a change
/// of contacts among them never needs fill outside it.
struct UpdatableLdlt {
    std::vector<int> perm;    // perm[i] = row of P A Pᵀ holding original row i
    std::vector<int> Lp, Li;  // CSC of the strictly lower part of L
    std::vector<double> Lx, D;
    std::vector<double> work;  // dense scratch, all zero between calls
    std::vector<int> path_a, path_b, path;

    template <class Ldlt> void copy_from(const Ldlt& ldlt) {
        const auto& L = ldlt.matrixL().nestedExpression();
        const auto n = static_cast<std::size_t>(L.outerSize());
        Lp.assign(L.outerIndexPtr(), L.outerIndexPtr() + n + 1);
        Li.assign(L.innerIndexPtr(), L.innerIndexPtr() + Lp.back());
        Lx.assign(L.valuePtr(), L.valuePtr() + Lp.back());
        const Eigen::VectorXd d = ldlt.vectorD();
        D.assign(d.data(), d.data() + n);
        const auto& P = ldlt.permutationP().indices();
        perm.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            perm[i] = P.size() ? static_cast<int>(P[static_cast<Eigen::Index>(i)]) : static_cast<int>(i);
        work.assign(n, 0.0);
    }

    int parent(int j) const { return Lp[j] < Lp[j + 1] ? Li[Lp[j]] : -1; }

    void walk(int j, std::vector<int>& out) const {
        out.clear();
        for (; j >= 0; j = parent(j)) out.push_back(j);
    }

    /// L D Lᵀ ← L D Lᵀ + σ w wᵀ with w = e_{P i} − e_{P j}.
    void modify(int i, int j, double sigma) {
        const int a = perm[static_cast<std::size_t>(i)], b = perm[static_cast<std::size_t>(j)];
        walk(a, path_a);
        walk(b, path_b);
        path.clear();
        std::set_union(path_a.begin(), path_a.end(), path_b.begin(), path_b.end(), std::back_inserter(path));
        work[static_cast<std::size_t>(a)] = 1.0;
        work[static_cast<std::size_t>(b)] = -1.0;
        double alpha = sigma;
        for (const int c : path) {
            const double p = work[static_cast<std::size_t>(c)];
            work[static_cast<std::size_t>(c)] = 0.0;
            if (p == 0.0) continue;
            const double d = D[static_cast<std::size_t>(c)];
            const double dbar = d + alpha * p * p;
            const double beta = p * alpha / dbar;
            alpha *= d / dbar;
            D[static_cast<std::size_t>(c)] = dbar;
            for (int k = Lp[c]; k < Lp[c + 1]; ++k) {
                double& w = work[static_cast<std::size_t>(Li[k])];
                w -= p * Lx[k];
                Lx[k] += beta * w;
            }
        }
    }

    /// u_x, u_y = A⁻¹ (b_x, b_y): both right-hand sides in one pass over L.
    void solve(const double* bx, const double* by, double* ux, double* uy) {
        const std::size_t n = D.size();
        y2.resize(2 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto r = static_cast<std::size_t>(perm[i]);
            y2[2 * r] = bx[i];
            y2[2 * r + 1] = by[i];
        }
        for (std::size_t c = 0; c < n; ++c) {  // L y = P b
            const double y0 = y2[2 * c], y1 = y2[2 * c + 1];
            for (int k = Lp[c]; k < Lp[c + 1]; ++k) {
                const auto r = static_cast<std::size_t>(Li[k]);
                y2[2 * r] -= Lx[k] * y0;
                y2[2 * r + 1] -= Lx[k] * y1;
            }
        }
        for (std::size_t c = 0; c < n; ++c) {
            y2[2 * c] /= D[c];
            y2[2 * c + 1] /= D[c];
        }
        for (std::size_t c = n; c-- > 0;) {  // Lᵀ x = y
            double s0 = y2[2 * c], s1 = y2[2 * c + 1];
            for (int k = Lp[c]; k < Lp[c + 1]; ++k) {
                const auto r = static_cast<std::size_t>(Li[k]);
                s0 -= Lx[k] * y2[2 * r];
                s1 -= Lx[k] * y2[2 * r + 1];
            }
            y2[2 * c] = s0;
            y2[2 * c + 1] = s1;
        }
        for (std::size_t i = 0; i < n; ++i) {
            const auto r = static_cast<std::size_t>(perm[i]);
            ux[i] = y2[2 * r];
            uy[i] = y2[2 * r + 1];
        }
    }
    std::vector<double> y2;  // interleaved (x, y) work vector in the permuted order
};

}  // namespace

struct EigenContactSolver::Impl {
    using Matrix = Eigen::SparseMatrix<double>;  // column-major; lower triangle is used
    Eigen::Index n;
    double delta;
    double rtol;
    Matrix A;
    Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;  // analysis and fresh factorisations
    UpdatableLdlt factor;                              // the factor in use, kept up to date
    std::size_t version = static_cast<std::size_t>(-1);
    std::vector<Eigen::Index> diag_slot, pair_slot;  // positions in A.valuePtr()
    std::vector<std::uint8_t> factored;              // contact set the factor represents
    bool have_factor = false;
    std::vector<ContactPair> contacts;  // current contacts, compacted for the residual check
    std::vector<double> residual;       // scratch of the residual check

    Eigen::Index slot(Eigen::Index row, Eigen::Index col) const {
        const auto* outer = A.outerIndexPtr();
        const auto* inner = A.innerIndexPtr();
        const auto* begin = inner + outer[col];
        const auto* end = inner + outer[col + 1];
        const auto* it = std::lower_bound(begin, end, static_cast<int>(row));
        if (it == end || *it != row) throw std::logic_error("CD0 Eigen solver: entry not in pattern");
        return static_cast<Eigen::Index>(it - inner);
    }

    void build_pattern(std::span<const ContactPair> pairs) {
        std::vector<Eigen::Triplet<double>> t;
        t.reserve(static_cast<std::size_t>(n) + pairs.size());
        for (Eigen::Index i = 0; i < n; ++i) t.emplace_back(i, i, 1.0);
        for (const auto& c : pairs)  // lower triangle: row > col; explicit zeros kept
            t.emplace_back(std::max(c.i, c.j), std::min(c.i, c.j), 0.0);
        A.resize(n, n);
        A.setFromTriplets(t.begin(), t.end());
        A.makeCompressed();
        diag_slot.resize(static_cast<std::size_t>(n));
        for (Eigen::Index i = 0; i < n; ++i) diag_slot[static_cast<std::size_t>(i)] = slot(i, i);
        pair_slot.resize(pairs.size());
        for (std::size_t k = 0; k < pairs.size(); ++k)
            pair_slot[k] = slot(std::max(pairs[k].i, pairs[k].j), std::min(pairs[k].i, pairs[k].j));
        ldlt.analyzePattern(A);
        have_factor = false;
    }

    void factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        double* v = A.valuePtr();
        for (auto s : diag_slot) v[s] = delta;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            // duplicate pairs cannot occur (the candidate list lists each pair once)
            const double c = in_contact[k] ? 1.0 : 0.0;
            v[pair_slot[k]] = -c;
            v[diag_slot[static_cast<std::size_t>(pairs[k].i)]] += c;
            v[diag_slot[static_cast<std::size_t>(pairs[k].j)]] += c;
        }
        ldlt.factorize(A);
        if (ldlt.info() != Eigen::Success) throw std::runtime_error("CD0 Eigen solver: factorisation failed");
        factor.copy_from(ldlt);
        factored.assign(in_contact.begin(), in_contact.end());
        have_factor = true;
    }

    // The factor's steps as solve_with_updated_factor calls them.
    bool adopt(std::span<const ContactPair> pairs, std::span<const std::int32_t> /*labels*/) {
        build_pattern(pairs);  // the Eigen factor is rebuilt with the pattern
        return false;
    }
    bool has_factor() const { return have_factor; }
    /// Rank-one changes for the contacts that formed or broke since the factor's contact set.
    int follow(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        int changes = 0;
        contacts.clear();
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            if (in_contact[k]) contacts.push_back(pairs[k]);
            if (in_contact[k] == factored[k]) continue;
            factor.modify(pairs[k].i, pairs[k].j, in_contact[k] ? 1.0 : -1.0);
            factored[k] = in_contact[k];
            ++changes;
        }
        return changes;
    }
    void apply(std::span<const double> bx, std::span<const double> by, std::span<double> ux, std::span<double> uy) {
        factor.solve(bx.data(), by.data(), ux.data(), uy.data());
    }
    int follow_and_apply(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                         std::span<const double> bx, std::span<const double> by, std::span<double> ux,
                         std::span<double> uy) {
        const int changes = follow(pairs, in_contact);
        apply(bx, by, ux, uy);
        return changes;
    }
    /// Whether ‖b − A u‖ ≤ rtol ‖b‖ for both right-hand sides and the current contacts.
    bool residual_within(std::span<const double> bx, std::span<const double> by, std::span<const double> ux,
                         std::span<const double> uy) {
        return contact_residual_within(bx, by, ux, uy, delta, contacts, rtol, residual);
    }
};

EigenContactSolver::EigenContactSolver(std::size_t n, double delta, double rtol) : impl_(new Impl{}) {
    impl_->n = static_cast<Eigen::Index>(n);
    impl_->delta = delta;
    impl_->rtol = rtol;
}

EigenContactSolver::~EigenContactSolver() = default;

SolveInfo EigenContactSolver::solve(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact,
                                    std::size_t pattern_version, std::span<const std::int32_t> labels,
                                    std::span<const double> b_x, std::span<const double> b_y, std::span<double> u_x,
                                    std::span<double> u_y) {
    Impl& m = *impl_;
    return solve_with_updated_factor(m, m.version, pairs, in_contact, pattern_version, labels, b_x, b_y, u_x, u_y);
}

}  // namespace jamsim::linalg

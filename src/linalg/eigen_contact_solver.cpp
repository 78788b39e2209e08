#include "jamsim/linalg/eigen_contact_solver.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace jamsim::linalg {

struct EigenContactSolver::Impl {
    using Matrix = Eigen::SparseMatrix<double>;  // column-major; lower triangle is used
    Eigen::Index n;
    double delta;
    double rtol;
    Matrix A;
    Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;
    std::size_t version = static_cast<std::size_t>(-1);
    std::vector<Eigen::Index> diag_slot, pair_slot;  // positions in A.valuePtr()
    std::vector<std::uint8_t> factored;              // contact set of the current factor
    bool have_factor = false;
    std::size_t factorizations = 0;
    Eigen::VectorXd r, z, p, q;  // PCG work vectors

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
        for (const auto& c : pairs)  // lower triangle: row > col
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
            // duplicate pairs cannot occur (the neighbour list lists each pair once)
            const double c = in_contact[k] ? 1.0 : 0.0;
            v[pair_slot[k]] = -c;
            v[diag_slot[static_cast<std::size_t>(pairs[k].i)]] += c;
            v[diag_slot[static_cast<std::size_t>(pairs[k].j)]] += c;
        }
        ldlt.factorize(A);
        if (ldlt.info() != Eigen::Success)
            throw std::runtime_error("CD0 Eigen solver: factorisation failed");
        factored.assign(in_contact.begin(), in_contact.end());
        have_factor = true;
        ++factorizations;
    }

    /// Contacts (i, j) of the current solve, compacted so the products below are branch-free.
    std::vector<ContactPair> contacts;
    void collect(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        contacts.clear();
        for (std::size_t k = 0; k < pairs.size(); ++k)
            if (in_contact[k]) contacts.push_back(pairs[k]);
    }

    /// out = A u for the current contacts: (A u)_i = δ u_i + Σ_{j in contact} (u_i − u_j).
    void multiply(const Eigen::VectorXd& u, Eigen::VectorXd& out) const {
        out = delta * u;
        double* o = out.data();
        const double* v = u.data();
        for (const auto& c : contacts) {
            const double d = v[c.i] - v[c.j];
            o[c.i] += d;
            o[c.j] -= d;
        }
    }

    /// Conjugate gradients preconditioned by the (stale) factor: the contact set differs from
    /// the factored one by a few contacts, a low-rank change, so CG needs about one iteration
    /// per changed contact. Returns the iterations, or −1 when they exceed `limit`.
    int pcg(const Eigen::Map<const Eigen::VectorXd>& b, Eigen::Map<Eigen::VectorXd>& u, int limit) {
        const double target = rtol * b.norm();
        multiply(u, q);
        r = b - q;
        if (r.norm() <= target) return 0;
        z = ldlt.solve(r);
        p = z;
        double rz = r.dot(z);
        for (int it = 1; it <= limit; ++it) {
            multiply(p, q);
            const double alpha = rz / p.dot(q);
            u += alpha * p;
            r -= alpha * q;
            if (r.norm() <= target) return it;
            z = ldlt.solve(r);
            const double rz_next = r.dot(z);
            p = z + (rz_next / rz) * p;
            rz = rz_next;
        }
        return -1;
    }
};

EigenContactSolver::EigenContactSolver(std::size_t n, double delta, double rtol)
    : impl_(new Impl{}) {
    impl_->n = static_cast<Eigen::Index>(n);
    impl_->delta = delta;
    impl_->rtol = rtol;
}

EigenContactSolver::~EigenContactSolver() = default;

std::size_t EigenContactSolver::factorizations() const { return impl_->factorizations; }

SolveInfo EigenContactSolver::solve(std::span<const ContactPair> pairs,
                                    std::span<const std::uint8_t> in_contact,
                                    std::size_t pattern_version, std::span<const double> b_x,
                                    std::span<const double> b_y, std::span<double> u_x,
                                    std::span<double> u_y) {
    Impl& m = *impl_;
    if (pattern_version != m.version) {
        m.build_pattern(pairs);
        m.version = pattern_version;
    }
    const Eigen::Map<const Eigen::VectorXd> bx(b_x.data(), m.n), by(b_y.data(), m.n);
    Eigen::Map<Eigen::VectorXd> ux(u_x.data(), m.n), uy(u_y.data(), m.n);
    const bool same = m.have_factor && std::equal(in_contact.begin(), in_contact.end(),
                                                  m.factored.begin(), m.factored.end());
    if (same) {  // the factor is exact for this contact set
        ux = m.ldlt.solve(bx);
        uy = m.ldlt.solve(by);
        return {0, 0};
    }
    if (m.have_factor) {  // warm-started PCG on the stale factor; refactorise if it struggles
        const Eigen::VectorXd ux0 = ux, uy0 = uy;
        m.collect(pairs, in_contact);
        const int itx = m.pcg(bx, ux, refresh_iterations);
        const int ity = itx < 0 ? -1 : m.pcg(by, uy, refresh_iterations);
        if (itx >= 0 && ity >= 0) return {itx, ity};
        ux = ux0;
        uy = uy0;
    }
    m.factorize(pairs, in_contact);
    ux = m.ldlt.solve(bx);
    uy = m.ldlt.solve(by);
    return {0, 0, true};
}

} // namespace jamsim::linalg

#include "jamsim/linalg/eigen_contact_solver.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <stdexcept>
#include <vector>

namespace jamsim::linalg {

struct EigenContactSolver::Impl {
    using Matrix = Eigen::SparseMatrix<double>;  // column-major; lower triangle is used
    Eigen::Index n;
    double delta;
    Matrix A;
    Eigen::SimplicialLDLT<Matrix, Eigen::Lower> ldlt;
    std::size_t version = static_cast<std::size_t>(-1);
    std::vector<Eigen::Index> diag_slot, pair_slot;  // positions in A.valuePtr()

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
        for (const auto& p : pairs)  // lower triangle: row > col
            t.emplace_back(std::max(p.i, p.j), std::min(p.i, p.j), 0.0);
        A.resize(n, n);
        A.setFromTriplets(t.begin(), t.end());
        A.makeCompressed();
        diag_slot.resize(static_cast<std::size_t>(n));
        for (Eigen::Index i = 0; i < n; ++i) diag_slot[static_cast<std::size_t>(i)] = slot(i, i);
        pair_slot.resize(pairs.size());
        for (std::size_t k = 0; k < pairs.size(); ++k)
            pair_slot[k] = slot(std::max(pairs[k].i, pairs[k].j), std::min(pairs[k].i, pairs[k].j));
        ldlt.analyzePattern(A);
    }
};

EigenContactSolver::EigenContactSolver(std::size_t n, double delta) : impl_(new Impl{}) {
    impl_->n = static_cast<Eigen::Index>(n);
    impl_->delta = delta;
}

EigenContactSolver::~EigenContactSolver() = default;

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
    double* v = m.A.valuePtr();
    for (auto s : m.diag_slot) v[s] = m.delta;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        // duplicate pairs cannot occur (the neighbour list lists each pair once)
        const double c = in_contact[k] ? 1.0 : 0.0;
        v[m.pair_slot[k]] = -c;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].i)]] += c;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].j)]] += c;
    }
    m.ldlt.factorize(m.A);
    if (m.ldlt.info() != Eigen::Success)
        throw std::runtime_error("CD0 Eigen solver: factorisation failed");
    const Eigen::Map<const Eigen::VectorXd> bx(b_x.data(), m.n), by(b_y.data(), m.n);
    Eigen::Map<Eigen::VectorXd>(u_x.data(), m.n) = m.ldlt.solve(bx);
    Eigen::Map<Eigen::VectorXd>(u_y.data(), m.n) = m.ldlt.solve(by);
    return {1, 1};
}

} // namespace jamsim::linalg

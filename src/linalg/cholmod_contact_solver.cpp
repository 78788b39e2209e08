#include "jamsim/linalg/cholmod_contact_solver.hpp"

#include <cholmod.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace jamsim::linalg {

struct CholmodContactSolver::Impl {
    int n = 0;
    double delta = 0, rtol = 0;
    Ordering ordering = Ordering::metis;
    cholmod_common c{};
    cholmod_sparse* A = nullptr;   // lower triangle (stype −1), pattern = candidate pairs
    cholmod_factor* L = nullptr;
    cholmod_dense* B = nullptr;    // n × 2: (b_x, b_y)
    cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;  // solve2 results and workspace
    std::size_t version = static_cast<std::size_t>(-1);
    std::vector<int> diag_slot, pair_slot;  // positions in A->x
    std::vector<int> pinv;                  // pinv[i] = row of L holding original row i
    std::vector<std::uint8_t> factored;     // contact set the factor represents
    bool have_factor = false;
    std::vector<ContactPair> contacts;      // current contacts (residual check)
    std::vector<double> rx, ry;
    std::vector<std::size_t> formed, broken;

    void fail(const char* what) const {
        throw std::runtime_error(std::string("CD0 CHOLMOD solver: ") + what + " failed (status " +
                                 std::to_string(c.status) + ")");
    }

    void free_all() {
        if (A) cholmod_free_sparse(&A, &c);
        if (L) cholmod_free_factor(&L, &c);
        if (B) cholmod_free_dense(&B, &c);
        if (X) cholmod_free_dense(&X, &c);
        if (Y) cholmod_free_dense(&Y, &c);
        if (E) cholmod_free_dense(&E, &c);
    }

    /// A's pattern: the diagonal and every candidate pair (explicit zeros for pairs that do
    /// not touch), lower triangle, sorted columns; then the symbolic analysis.
    void build_pattern(std::span<const ContactPair> pairs) {
        if (A) cholmod_free_sparse(&A, &c);
        if (L) cholmod_free_factor(&L, &c);
        std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
        for (const auto& p : pairs) ++count[static_cast<std::size_t>(std::min(p.i, p.j)) + 1];
        for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) count[j + 1] += count[j] + 1;
        const std::size_t nnz = static_cast<std::size_t>(count.back());
        A = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz,
                                    1, 1, -1, CHOLMOD_REAL, &c);
        if (!A) fail("cholmod_allocate_sparse");
        auto* Ap = static_cast<int*>(A->p);
        auto* Ai = static_cast<int*>(A->i);
        std::copy(count.begin(), count.end(), Ap);
        std::vector<int> fill(count.begin(), count.end() - 1);
        diag_slot.resize(static_cast<std::size_t>(n));
        for (int j = 0; j < n; ++j) {
            diag_slot[static_cast<std::size_t>(j)] = fill[static_cast<std::size_t>(j)];
            Ai[fill[static_cast<std::size_t>(j)]++] = j;
        }
        pair_slot.resize(pairs.size());
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const int lo = std::min(pairs[k].i, pairs[k].j), hi = std::max(pairs[k].i, pairs[k].j);
            pair_slot[k] = fill[static_cast<std::size_t>(lo)];
            Ai[fill[static_cast<std::size_t>(lo)]++] = hi;
        }
        // Sort each column's rows (carrying the pair slots along): CHOLMOD wants sorted columns.
        std::vector<int> where(nnz);  // where[s] = pair index + 1 at slot s (0: diagonal)
        for (std::size_t k = 0; k < pairs.size(); ++k) where[static_cast<std::size_t>(pair_slot[k])] = static_cast<int>(k) + 1;
        std::vector<std::pair<int, int>> col;
        for (int j = 0; j < n; ++j) {
            col.clear();
            for (int s = Ap[j]; s < Ap[j + 1]; ++s) col.emplace_back(Ai[s], where[static_cast<std::size_t>(s)]);
            std::sort(col.begin(), col.end());
            for (std::size_t t = 0; t < col.size(); ++t) {
                const int s = Ap[j] + static_cast<int>(t);
                Ai[s] = col[t].first;
                if (col[t].second == 0) diag_slot[static_cast<std::size_t>(j)] = s;
                else pair_slot[static_cast<std::size_t>(col[t].second - 1)] = s;
            }
        }
        L = cholmod_analyze(A, &c);
        if (!L) fail("cholmod_analyze");
        const auto* perm = static_cast<const int*>(L->Perm);
        pinv.resize(static_cast<std::size_t>(n));
        for (int k = 0; k < n; ++k) pinv[static_cast<std::size_t>(perm[k])] = k;
        have_factor = false;
    }

    void factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
        auto* v = static_cast<double*>(A->x);
        for (const int s : diag_slot) v[s] = delta;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            const double w = in_contact[k] ? 1.0 : 0.0;
            v[pair_slot[k]] = -w;
            v[diag_slot[static_cast<std::size_t>(pairs[k].i)]] += w;
            v[diag_slot[static_cast<std::size_t>(pairs[k].j)]] += w;
        }
        if (!cholmod_factorize(A, L, &c) || c.status != CHOLMOD_OK) fail("cholmod_factorize");
        factored.assign(in_contact.begin(), in_contact.end());
        have_factor = true;
    }

    /// LDLᵀ ← LDLᵀ ± W Wᵀ, W's columns P (e_i − e_j) for the listed pairs (up to all at once).
    void modify(bool update, std::span<const ContactPair> pairs, const std::vector<std::size_t>& which) {
        if (which.empty()) return;
        const std::size_t k = which.size();
        cholmod_sparse* W = cholmod_allocate_sparse(static_cast<std::size_t>(n), k, 2 * k, 1, 1, 0,
                                                    CHOLMOD_REAL, &c);
        if (!W) fail("cholmod_allocate_sparse");
        auto* Wp = static_cast<int*>(W->p);
        auto* Wi = static_cast<int*>(W->i);
        auto* Wx = static_cast<double*>(W->x);
        for (std::size_t t = 0; t < k; ++t) {
            int a = pinv[static_cast<std::size_t>(pairs[which[t]].i)];
            int b = pinv[static_cast<std::size_t>(pairs[which[t]].j)];
            double va = 1.0, vb = -1.0;
            if (a > b) {
                std::swap(a, b);
                std::swap(va, vb);
            }
            Wp[t] = static_cast<int>(2 * t);
            Wi[2 * t] = a;
            Wx[2 * t] = va;
            Wi[2 * t + 1] = b;
            Wx[2 * t + 1] = vb;
        }
        Wp[k] = static_cast<int>(2 * k);
        const int ok = cholmod_updown(update ? 1 : 0, W, L, &c);
        cholmod_free_sparse(&W, &c);
        if (!ok || c.status != CHOLMOD_OK) fail("cholmod_updown");
    }

    void solve(std::span<const double> bx, std::span<const double> by, std::span<double> ux,
               std::span<double> uy) {
        auto* b = static_cast<double*>(B->x);
        std::copy(bx.begin(), bx.end(), b);
        std::copy(by.begin(), by.end(), b + n);
        if (!cholmod_solve2(CHOLMOD_A, L, B, nullptr, &X, nullptr, &Y, &E, &c)) fail("cholmod_solve2");
        const auto* x = static_cast<const double*>(X->x);
        std::copy(x, x + n, ux.begin());
        std::copy(x + n, x + 2 * n, uy.begin());
    }

    /// Whether ‖b − A u‖ ≤ rtol ‖b‖ for both right-hand sides and the current contacts.
    bool converged(std::span<const double> bx, std::span<const double> by,
                   std::span<const double> ux, std::span<const double> uy) {
        return contact_residual_within(bx, by, ux, uy, delta, contacts, rtol, rx, ry);
    }
};

CholmodContactSolver::CholmodContactSolver(std::size_t n, double delta, Ordering ordering,
                                           double rtol)
    : impl_(new Impl{}) {
    Impl& m = *impl_;
    m.n = static_cast<int>(n);
    m.delta = delta;
    m.rtol = rtol;
    m.ordering = ordering;
    cholmod_start(&m.c);
    m.c.print = 0;
    m.c.error_handler = nullptr;
    m.c.supernodal = CHOLMOD_SIMPLICIAL;  // updown needs a simplicial LDLᵀ
    m.c.final_ll = 0;
    m.c.nmethods = 1;
    m.c.method[0].ordering = ordering == Ordering::metis ? CHOLMOD_METIS : CHOLMOD_AMD;
    m.c.postorder = 1;
    m.B = cholmod_allocate_dense(n, 2, n, CHOLMOD_REAL, &m.c);
    if (!m.B) {
        cholmod_finish(&m.c);
        throw std::runtime_error("CD0 CHOLMOD solver: cannot allocate");
    }
}

CholmodContactSolver::~CholmodContactSolver() {
    if (!impl_) return;
    impl_->free_all();
    cholmod_finish(&impl_->c);
}

SolveInfo CholmodContactSolver::solve(std::span<const ContactPair> pairs,
                                      std::span<const std::uint8_t> in_contact,
                                      std::size_t pattern_version, std::span<const double> b_x,
                                      std::span<const double> b_y, std::span<double> u_x,
                                      std::span<double> u_y) {
    Impl& m = *impl_;
    if (pattern_version != m.version || !m.L) {
        m.build_pattern(pairs);
        m.version = pattern_version;
    }
    if (m.have_factor) {  // bring the factor to the current contacts: one update, one downdate
        m.formed.clear();
        m.broken.clear();
        m.contacts.clear();
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            if (in_contact[k]) m.contacts.push_back(pairs[k]);
            if (in_contact[k] == m.factored[k]) continue;
            (in_contact[k] ? m.formed : m.broken).push_back(k);
            m.factored[k] = in_contact[k];
        }
        const int changes = static_cast<int>(m.formed.size() + m.broken.size());
        m.modify(true, pairs, m.formed);  // update first: the factor stays well away from singular
        m.modify(false, pairs, m.broken);
        m.solve(b_x, b_y, u_x, u_y);
        if (changes == 0) return {0, 0, false, 0};
        if (m.converged(b_x, b_y, u_x, u_y)) return {0, 0, false, changes};
    }
    m.factorize(pairs, in_contact);
    m.solve(b_x, b_y, u_x, u_y);
    return {0, 0, true, 0};
}

} // namespace jamsim::linalg

#include "cholmod_factor.hpp"

#include <cholmod.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace jamsim::linalg {

struct CholmodUpdatedFactor::Impl {
    int n = 0;
    double delta = 0;
    cholmod_common c{};
    cholmod_sparse* A = nullptr;   // lower triangle (stype −1), pattern = candidate pairs
    cholmod_factor* L = nullptr;
    cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;  // solve2 result and workspace
    std::vector<int> diag_slot, pair_slot;  // positions in A->x
    std::vector<int> pinv;                  // pinv[i] = row of L holding original row i
    bool analysis_current = false;          // A and the analysis are of the current pairs
    std::vector<std::int32_t> labels;       // labels of the rows at the last factorize/adopt
    double fresh_fill = 0;                  // entries of L after the last fresh factor
    std::vector<int> scratch;

    double fill() const {
        const auto* nz = static_cast<const int*>(L->nz);
        double total = 0;
        for (int j = 0; j < n; ++j) total += nz[j];
        return total;
    }
    std::vector<std::uint8_t> factored;     // contact set the factor represents
    bool have_factor = false;
    std::vector<ContactPair> contacts;      // contacts of the last factorize() or follow()
    std::vector<std::size_t> formed, broken;

    void fail(const char* what) const {
        throw std::runtime_error(std::string("CD0 CHOLMOD factor: ") + what + " failed (status " +
                                 std::to_string(c.status) + ")");
    }

    /// LDLᵀ ← LDLᵀ ± W Wᵀ, W's columns P (e_i − e_j) for the listed pairs (all at once).
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
};

CholmodUpdatedFactor::CholmodUpdatedFactor(std::size_t n, double delta, Ordering ordering)
    : impl_(new Impl{}) {
    Impl& m = *impl_;
    m.n = static_cast<int>(n);
    m.delta = delta;
    cholmod_start(&m.c);
    m.c.print = 0;
    m.c.error_handler = nullptr;
    m.c.supernodal = CHOLMOD_SIMPLICIAL;  // updown needs a simplicial LDLᵀ
    m.c.final_ll = 0;
    m.c.nmethods = 1;
    m.c.method[0].ordering = ordering == Ordering::metis ? CHOLMOD_METIS : CHOLMOD_AMD;
    m.c.postorder = 1;
}

CholmodUpdatedFactor::~CholmodUpdatedFactor() {
    Impl& m = *impl_;
    if (m.A) cholmod_free_sparse(&m.A, &m.c);
    if (m.L) cholmod_free_factor(&m.L, &m.c);
    if (m.X) cholmod_free_dense(&m.X, &m.c);
    if (m.Y) cholmod_free_dense(&m.Y, &m.c);
    if (m.E) cholmod_free_dense(&m.E, &m.c);
    cholmod_finish(&m.c);
}

bool CholmodUpdatedFactor::has_factor() const { return impl_->have_factor; }

std::span<const ContactPair> CholmodUpdatedFactor::contacts() const { return impl_->contacts; }

void CholmodUpdatedFactor::analyse(std::span<const ContactPair> pairs) {
    Impl& m = *impl_;
    const int n = m.n;
    if (m.A) cholmod_free_sparse(&m.A, &m.c);
    if (m.L) cholmod_free_factor(&m.L, &m.c);
    m.have_factor = false;
    // A's pattern: the diagonal and every candidate pair, lower triangle, sorted columns.
    std::vector<int> count(static_cast<std::size_t>(n) + 1, 0);
    for (const auto& p : pairs) ++count[static_cast<std::size_t>(std::min(p.i, p.j)) + 1];
    for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) count[j + 1] += count[j] + 1;
    const std::size_t nnz = static_cast<std::size_t>(count.back());
    m.A = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz, 1,
                                  1, -1, CHOLMOD_REAL, &m.c);
    if (!m.A) m.fail("cholmod_allocate_sparse");
    auto* Ap = static_cast<int*>(m.A->p);
    auto* Ai = static_cast<int*>(m.A->i);
    std::copy(count.begin(), count.end(), Ap);
    std::vector<int> fill(count.begin(), count.end() - 1);
    m.diag_slot.resize(static_cast<std::size_t>(n));
    for (int j = 0; j < n; ++j) {
        m.diag_slot[static_cast<std::size_t>(j)] = fill[static_cast<std::size_t>(j)];
        Ai[fill[static_cast<std::size_t>(j)]++] = j;
    }
    m.pair_slot.resize(pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const int lo = std::min(pairs[k].i, pairs[k].j), hi = std::max(pairs[k].i, pairs[k].j);
        m.pair_slot[k] = fill[static_cast<std::size_t>(lo)];
        Ai[fill[static_cast<std::size_t>(lo)]++] = hi;
    }
    // Sort each column's rows (carrying the pair slots along): CHOLMOD wants sorted columns.
    std::vector<int> where(nnz);  // where[s] = pair index + 1 at slot s (0: diagonal)
    for (std::size_t k = 0; k < pairs.size(); ++k)
        where[static_cast<std::size_t>(m.pair_slot[k])] = static_cast<int>(k) + 1;
    std::vector<std::pair<int, int>> col;
    for (int j = 0; j < n; ++j) {
        col.clear();
        for (int s = Ap[j]; s < Ap[j + 1]; ++s) col.emplace_back(Ai[s], where[static_cast<std::size_t>(s)]);
        std::sort(col.begin(), col.end());
        for (std::size_t t = 0; t < col.size(); ++t) {
            const int s = Ap[j] + static_cast<int>(t);
            Ai[s] = col[t].first;
            if (col[t].second == 0) m.diag_slot[static_cast<std::size_t>(j)] = s;
            else m.pair_slot[static_cast<std::size_t>(col[t].second - 1)] = s;
        }
    }
    m.L = cholmod_analyze(m.A, &m.c);
    if (!m.L) m.fail("cholmod_analyze");
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.pinv.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) m.pinv[static_cast<std::size_t>(perm[k])] = k;
    m.analysis_current = true;
}

bool CholmodUpdatedFactor::adopt(std::span<const ContactPair> pairs,
                                 std::span<const std::int32_t> labels) {
    Impl& m = *impl_;
    m.analysis_current = false;
    const auto n = static_cast<std::size_t>(m.n);
    if (!m.have_factor || labels.size() != n || m.labels.size() != n ||
        m.fill() > kFillGrowth * m.fresh_fill) {
        m.have_factor = false;
        m.labels.assign(labels.begin(), labels.end());
        return false;
    }
    // Row of L of each label, then the new rows' positions: the same disks, the same order.
    std::vector<int>& row_of_label = m.scratch;
    row_of_label.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) row_of_label[static_cast<std::size_t>(m.labels[i])] = m.pinv[i];
    std::vector<int> new_index(n, -1);  // by label
    for (std::size_t i = 0; i < n; ++i) {
        const auto label = static_cast<std::size_t>(labels[i]);
        if (label >= n || new_index[label] >= 0) throw std::invalid_argument("CD0 CHOLMOD factor: labels are not a permutation");
        new_index[label] = static_cast<int>(i);
    }
    auto* perm = static_cast<int*>(m.L->Perm);
    for (std::size_t i = 0; i < n; ++i) {
        const int row = row_of_label[static_cast<std::size_t>(labels[i])];
        m.pinv[i] = row;
        perm[row] = static_cast<int>(i);
    }
    // The factor's contacts in the new numbering, matched against the new candidate pairs.
    auto key = [](int a, int b) {
        return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
    };
    std::vector<std::uint64_t> held;
    held.reserve(m.contacts.size());
    std::vector<ContactPair> renamed;
    renamed.reserve(m.contacts.size());
    for (const ContactPair& c : m.contacts) {
        const int a = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.i)])];
        const int b = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.j)])];
        renamed.push_back({a, b});
        held.push_back(key(a, b));
    }
    std::vector<std::uint64_t> sorted = held;
    std::sort(sorted.begin(), sorted.end());
    std::vector<std::uint8_t> found(sorted.size(), 0);
    m.factored.assign(pairs.size(), 0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto at = std::lower_bound(sorted.begin(), sorted.end(), key(pairs[k].i, pairs[k].j));
        if (at == sorted.end() || *at != key(pairs[k].i, pairs[k].j)) continue;
        m.factored[k] = 1;
        found[static_cast<std::size_t>(at - sorted.begin())] = 1;
    }
    // Contacts of the factor that are no candidates any more (they broke): downdated now.
    std::vector<std::size_t> gone;
    for (std::size_t t = 0; t < renamed.size(); ++t) {
        const auto at = std::lower_bound(sorted.begin(), sorted.end(), held[t]);
        if (!found[static_cast<std::size_t>(at - sorted.begin())]) gone.push_back(t);
    }
    m.modify(false, renamed, gone);
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k)
        if (m.factored[k]) m.contacts.push_back(pairs[k]);
    m.labels.assign(labels.begin(), labels.end());
    return true;
}

void CholmodUpdatedFactor::factorize(std::span<const ContactPair> pairs,
                                     std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    if (!m.analysis_current) analyse(pairs);
    auto* v = static_cast<double*>(m.A->x);
    for (const int s : m.diag_slot) v[s] = m.delta;
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (in_contact[k]) m.contacts.push_back(pairs[k]);
        const double w = in_contact[k] ? 1.0 : 0.0;
        v[m.pair_slot[k]] = -w;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].i)]] += w;
        v[m.diag_slot[static_cast<std::size_t>(pairs[k].j)]] += w;
    }
    if (!cholmod_factorize(m.A, m.L, &m.c) || m.c.status != CHOLMOD_OK) m.fail("cholmod_factorize");
    m.factored.assign(in_contact.begin(), in_contact.end());
    m.have_factor = true;
    m.fresh_fill = m.fill();
}

int CholmodUpdatedFactor::follow(std::span<const ContactPair> pairs,
                                 std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    m.formed.clear();
    m.broken.clear();
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (in_contact[k]) m.contacts.push_back(pairs[k]);
        if (in_contact[k] == m.factored[k]) continue;
        (in_contact[k] ? m.formed : m.broken).push_back(k);
        m.factored[k] = in_contact[k];
    }
    m.modify(true, pairs, m.formed);  // update first: the factor stays well away from singular
    m.modify(false, pairs, m.broken);
    return static_cast<int>(m.formed.size() + m.broken.size());
}

void CholmodUpdatedFactor::solve(const double* b, double* x) {
    Impl& m = *impl_;
    cholmod_dense B{};  // a view of b: n × 2, column major
    B.nrow = static_cast<std::size_t>(m.n);
    B.ncol = 2;
    B.nzmax = 2 * B.nrow;
    B.d = B.nrow;
    B.x = const_cast<double*>(b);
    B.xtype = CHOLMOD_REAL;
    B.dtype = CHOLMOD_DOUBLE;
    if (!cholmod_solve2(CHOLMOD_A, m.L, &B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.c))
        m.fail("cholmod_solve2");
    const auto* out = static_cast<const double*>(m.X->x);
    std::copy(out, out + 2 * m.n, x);
}

} // namespace jamsim::linalg

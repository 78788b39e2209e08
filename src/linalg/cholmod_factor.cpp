#include "cholmod_factor_impl.hpp"

#include <omp.h>

namespace jamsim::linalg {

using factor_kernels::ScopeTimer;

void CholmodUpdatedFactor::Impl::modify(bool update, std::span<const ContactPair> pairs,
                                        const std::vector<std::size_t>& which) {
    if (which.empty()) return;
    const std::size_t k = which.size();
    cholmod_sparse* W = cholmod_allocate_sparse(static_cast<std::size_t>(n), k, 2 * k, 1, 1, 0, CHOLMOD_REAL, &c);
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
    etree.clear();           // an update may have added fill
    split_computed = false;  // its tails (offsets into L) are stale until find_etree_if_stale
    cholmod_free_sparse(&W, &c);
    if (!ok || c.status != CHOLMOD_OK) fail("cholmod_updown");
}

CholmodUpdatedFactor::CholmodUpdatedFactor(std::size_t n, double delta, Ordering ordering, Vectors vectors)
    : impl_(new Impl{}) {
    Impl& m = *impl_;
    m.n = static_cast<int>(n);
    m.delta = delta;
    const factor_kernels::WideKernels kernels = factor_kernels::choose_kernels(vectors);
    for (factor_kernels::SweepColumns* cols : {&m.columns, &m.second_columns}) {  // one per thread
        cols->consecutive_kernel = kernels.one;
        cols->consecutive2_kernel = kernels.two;
        cols->vector_kernels = kernels.name;
    }
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
    cholmod_finish(&m.c);
}

const char* CholmodUpdatedFactor::vector_kernels() const { return impl_->columns.vector_kernels; }

bool CholmodUpdatedFactor::has_factor() const { return impl_->have_factor; }

CholmodUpdatedFactor::Counts CholmodUpdatedFactor::counts() const {
    Counts c = impl_->counts;
    c.block_updates = impl_->columns.block_updates;
    return c;
}

std::span<const ContactPair> CholmodUpdatedFactor::contacts() const {
    return std::span<const ContactPair>(impl_->contacts).first(impl_->n_contacts);
}

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
    m.A = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz, 1, 1, -1, CHOLMOD_REAL,
                                  &m.c);
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
            if (col[t].second == 0)
                m.diag_slot[static_cast<std::size_t>(j)] = s;
            else
                m.pair_slot[static_cast<std::size_t>(col[t].second - 1)] = s;
        }
    }
    m.etree.clear();                                            // a new L: its tree and split afresh
    m.split_mid = m.split_top = m.kept_mid = m.kept_top = m.n;  // and no split kept (find_etree)
    m.L = cholmod_analyze(m.A, &m.c);
    if (!m.L) m.fail("cholmod_analyze");
    const auto* perm = static_cast<const int*>(m.L->Perm);
    m.pinv.resize(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) m.pinv[static_cast<std::size_t>(perm[k])] = k;
    m.analysis_current = true;
}

bool CholmodUpdatedFactor::adopt(std::span<const ContactPair> pairs, std::span<const std::int32_t> labels) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    m.analysis_current = false;
    const auto n = static_cast<std::size_t>(m.n);
    if (!m.have_factor || labels.size() != n || m.labels.size() != n || m.fill() > kFillGrowth * m.fresh_fill) {
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
        if (label >= n || new_index[label] >= 0)
            throw std::invalid_argument("CD0 CHOLMOD factor: labels are not a permutation");
        new_index[label] = static_cast<int>(i);
    }
    auto* perm = static_cast<int*>(m.L->Perm);
    for (std::size_t i = 0; i < n; ++i) {
        const int row = row_of_label[static_cast<std::size_t>(labels[i])];
        m.pinv[i] = row;
        perm[row] = static_cast<int>(i);
    }
    // The factor's contacts in the new numbering, grouped by their lower disk (a disk has a
    // few), then matched against the new candidate pairs.
    const std::span<const ContactPair> factor_contacts = contacts();
    const std::size_t held = factor_contacts.size();
    std::vector<ContactPair> renamed(held);
    std::vector<int> first(n + 1, 0);  // held contacts of lower disk d: [first[d], first[d + 1])
    for (std::size_t t = 0; t < held; ++t) {
        const ContactPair& c = factor_contacts[t];
        const int a = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.i)])];
        const int b = new_index[static_cast<std::size_t>(m.labels[static_cast<std::size_t>(c.j)])];
        renamed[t] = {a, b};
        ++first[static_cast<std::size_t>(std::min(a, b)) + 1];
    }
    for (std::size_t d = 0; d < n; ++d) first[d + 1] += first[d];
    std::vector<int> upper(held);          // the other disk of each grouped contact
    std::vector<std::size_t> which(held);  // and its place in `renamed`
    {
        std::vector<int> next(first.begin(), first.end() - 1);
        for (std::size_t t = 0; t < held; ++t) {
            const auto [a, b] = renamed[t];
            const auto at = static_cast<std::size_t>(next[static_cast<std::size_t>(std::min(a, b))]++);
            upper[at] = std::max(a, b);
            which[at] = t;
        }
    }
    std::vector<std::uint8_t> found(held, 0);
    m.factored.assign(pairs.size(), 0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        const auto lo = static_cast<std::size_t>(std::min(pairs[k].i, pairs[k].j));
        const int hi = std::max(pairs[k].i, pairs[k].j);
        for (int at = first[lo]; at < first[lo + 1]; ++at) {
            if (upper[static_cast<std::size_t>(at)] != hi) continue;
            m.factored[k] = 1;
            found[which[static_cast<std::size_t>(at)]] = 1;
            break;
        }
    }
    // Contacts of the factor that are no candidates any more (they broke): downdated now.
    std::vector<std::size_t> gone;
    for (std::size_t t = 0; t < held; ++t)
        if (!found[t]) gone.push_back(t);
    m.modify(false, renamed, gone);
    m.contacts.clear();
    for (std::size_t k = 0; k < pairs.size(); ++k)
        if (m.factored[k]) m.contacts.push_back(pairs[k]);
    m.n_contacts = m.contacts.size();
    m.labels.assign(labels.begin(), labels.end());
    return true;
}

void CholmodUpdatedFactor::factorize(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    bool fresh_timing = false;  // factorize does not nest
    const ScopeTimer fresh_timer(m.counts.fresh_seconds, fresh_timing);
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
    m.n_contacts = m.contacts.size();
    m.etree.clear();  // the pattern may change, and a failure leaves none to split
    m.split_mid = m.split_top = m.kept_mid = m.kept_top = m.n;  // and no split kept (find_etree)
    if (!cholmod_factorize(m.A, m.L, &m.c) || m.c.status != CHOLMOD_OK) m.fail("cholmod_factorize");
    m.factored.assign(in_contact.begin(), in_contact.end());
    m.have_factor = true;
    m.fresh_fill = m.fill();
}

std::size_t CholmodUpdatedFactor::Impl::gather_range(std::span<const ContactPair> pairs,
                                                     std::span<const std::uint8_t> in_contact, std::size_t from,
                                                     std::size_t stores_end, std::size_t to, std::size_t at,
                                                     std::vector<std::size_t>& formed_to,
                                                     std::vector<std::size_t>& broken_to) {
    ContactPair* const out = contacts.data() + at;
    std::size_t touching = 0;
    // Changes are rare, so their branch predicts well.
    auto take_change = [&](std::size_t k) {
        if (in_contact[k] == factored[k]) return;
        (in_contact[k] ? formed_to : broken_to).push_back(k);
        factored[k] = in_contact[k];
    };
    for (std::size_t k = from; k < stores_end; ++k) {
        out[touching] = pairs[k];
        touching += in_contact[k] != 0;
        take_change(k);
    }
    for (std::size_t k = stores_end; k < to; ++k) {
        if (in_contact[k]) out[touching++] = pairs[k];
        take_change(k);
    }
    return touching;
}

std::pair<int, std::size_t> CholmodUpdatedFactor::Impl::gather_changes(std::span<const ContactPair> pairs,
                                                                       std::span<const std::uint8_t> in_contact) {
    formed.clear();
    broken.clear();
    const std::size_t size = pairs.size();
    if (contacts.size() < size) contacts.resize(size);
    if (!two_threads(n) || size < kThreadedLoopMin) {
        n_contacts = gather_range(pairs, in_contact, 0, size, size, 0, formed, broken);
    } else {
        // Two threads, a half of the pairs each: the second's contacts go after the first's,
        // whose count it takes itself (a count of flags, far cheaper than the pass), and its
        // changes after the first's, so the lists are those of one pass. The first thread's
        // stores without a branch end at its last contact: one past it would land on the
        // second thread's first.
        const std::size_t half = size / 2;
        std::size_t last_touching = half;
        while (last_touching > 0 && !in_contact[last_touching - 1]) --last_touching;
        formed_second.clear();
        broken_second.clear();
        std::size_t touching[2] = {0, 0};
        {
            const TimedRegion timed;
#pragma omp parallel num_threads(2)
            {
                const int thread = omp_get_thread_num();
                const bool alone = omp_get_num_threads() == 1;  // a team of one takes both halves
                if (thread == 0)
                    touching[0] = gather_range(pairs, in_contact, 0, last_touching, half, 0, formed, broken);
                if (thread == 1 || alone) {
                    std::size_t before = 0;
                    for (std::size_t k = 0; k < half; ++k) before += in_contact[k] != 0;
                    touching[1] =
                        gather_range(pairs, in_contact, half, size, size, before, formed_second, broken_second);
                }
            }
        }
        formed.insert(formed.end(), formed_second.begin(), formed_second.end());
        broken.insert(broken.end(), broken_second.begin(), broken_second.end());
        n_contacts = touching[0] + touching[1];
    }
    // Changes whose pattern L holds go through `sweep`, updates first (the factor stays well
    // away from singular), in one pass; contacts formed outside the pattern (possible after
    // `adopt`) make fill, which CHOLMOD's update allocates.
    sweep_rows.clear();
    outside.clear();
    int a = 0, b = 0;
    for (const std::size_t k : formed) {
        if (fits(pairs[k], a, b))
            sweep_rows.emplace_back(a, b);
        else
            outside.push_back(k);
    }
    const std::size_t n_up = sweep_rows.size();
    for (const std::size_t k : broken) {
        if (!fits(pairs[k], a, b)) throw std::logic_error("CD0 CHOLMOD factor: a broken contact outside L's pattern");
        sweep_rows.emplace_back(a, b);
    }
    modify(true, pairs, outside);
    counts.swept += static_cast<long>(sweep_rows.size());
    counts.filled += static_cast<long>(outside.size());
    return {static_cast<int>(formed.size() + broken.size()), n_up};
}

int CholmodUpdatedFactor::follow(std::span<const ContactPair> pairs, std::span<const std::uint8_t> in_contact) {
    Impl& m = *impl_;
    const ScopeTimer timer(m.counts.upkeep_seconds, m.timing);
    const auto [changes, n_up] = m.gather_changes(pairs, in_contact);
    m.sweep(m.sweep_rows, n_up);
    if (std::exchange(m.columns.failed, false)) {  // a downdate lost positive definiteness (round-off): start afresh
        ++m.counts.refactored;
        factorize(pairs, in_contact);
    }
    return changes;
}

}  // namespace jamsim::linalg

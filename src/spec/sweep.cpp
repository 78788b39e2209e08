// A campaign file's [sweep] expanded into replicas (sweep.hpp).
#include "sweep.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <map>
#include <set>
#include <tuple>
#include <unordered_map>

#include "jamsim/core/memory.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim::spec_detail {

namespace {

struct Point {
    std::int64_t n;
    double phi, rate;
    std::vector<std::uint64_t> seeds;  ///< its own seeds (a point's `seeds`); empty: the sweep's
    std::string where;                 ///< "[sweep] points[k]" for a listed point; empty: the grid's
};

/// The sweep's seeds: a list, or `seeds = K` (seeds 1..K, listed once the sweep's size is
/// checked: `count`), or seed 1.
struct Seeds {
    std::vector<std::uint64_t> listed;
    std::int64_t count = 0;
};

Seeds read_seeds(const Reader& r, const toml::table& sweep) {
    Seeds out;
    std::vector<std::uint64_t>& seeds = out.listed;
    std::int64_t& seed_count = out.count;
    if (const toml::node* s = sweep.get("seeds"); s && !s->is_array()) {
        seed_count = r.integer(*s, "[sweep] seeds");
        if (seed_count < 1) r.fail("[sweep] seeds", show(*s), "a count >= 1 or a list of seeds");
    } else if (s) {
        r.each(sweep, "[sweep]", "seeds", [&](const toml::node& n, const std::string& where) {
            const auto v = r.integer(n, where);
            if (v < 0) r.fail(where, show(n), "a seed >= 0");
            seeds.push_back(static_cast<std::uint64_t>(v));
        });
    } else {
        seeds.push_back(1);
    }

    return out;
}

/// Reads the sweep's numbers: phi and rate as numbers; a rate other than 0 only for models
/// that shear.
class SweepNumbers {
  public:
    SweepNumbers(const Reader& r, const ReplicaParams& base, bool uses_rate)
        : r_(r), base_(base), uses_rate_(uses_rate) {}
    double operator()(const toml::node& n, const std::string& where, const char* key) const {
        const auto v = n.value<double>();
        if (!v || !(n.is_floating_point() || n.is_integer())) r_.fail(where, show(n), "a number");
        if (std::string(key) == "rate" && !uses_rate_ && *v != 0.0)
            r_.fail(where, show(n), "0 or no rate: " + base_.model + " does not use a shear rate");
        return *v;
    }

  private:
    const Reader& r_;
    const ReplicaParams& base_;
    bool uses_rate_;
};

/// The grid's points (every N x phi x rate), at most max_replicas of them.
void read_grid(const Reader& r, const toml::table& sweep, const SweepNumbers& sweep_number, bool uses_rate,
               std::int64_t max_replicas, std::vector<Point>& points) {
    const bool grid = sweep.get("N") || sweep.get("phi") || sweep.get("rate");
    if (grid) {
        std::vector<std::int64_t> ns;
        std::vector<double> phis, rates;
        r.each(sweep, "[sweep]", "N",
               [&](const toml::node& n, const std::string& w) { ns.push_back(r.integer(n, w)); });
        r.each(sweep, "[sweep]", "phi",
               [&](const toml::node& n, const std::string& w) { phis.push_back(sweep_number(n, w, "phi")); });
        if (uses_rate || sweep.get("rate"))
            r.each(sweep, "[sweep]", "rate",
                   [&](const toml::node& n, const std::string& w) { rates.push_back(sweep_number(n, w, "rate")); });
        else
            rates.push_back(0.0);
        const double grid_size =
            static_cast<double>(ns.size()) * static_cast<double>(phis.size()) * static_cast<double>(rates.size());
        if (grid_size > static_cast<double>(max_replicas))
            r.fail("[sweep]",
                   std::to_string(ns.size()) + " N x " + std::to_string(phis.size()) + " phi x " +
                       std::to_string(rates.size()) + " rate",
                   "at most " + std::to_string(max_replicas) + " replicas (jamsim run --max-replicas raises the cap)");
        for (auto n : ns)
            for (double phi : phis)
                for (double rate : rates) points.push_back({n, phi, rate, {}, {}});
    }
}

/// The listed points (`points = [{N = .., phi = .., rate = .., seeds = [..]}, ...]`).
void read_points(const Reader& r, const toml::table& sweep, const SweepNumbers& sweep_number, bool uses_rate,
                 std::int64_t max_replicas, std::vector<Point>& points) {
    if (const toml::node* p = sweep.get("points")) {
        const toml::array* arr = p->as_array();
        if (!arr) r.fail("[sweep] points", show(*p), "a list of {N = .., phi = .., rate = ..}");
        for (std::size_t k = 0; k < arr->size(); ++k) {
            const std::string where = "[sweep] points[" + std::to_string(k) + "]";
            const toml::table* t = arr->get(k)->as_table();
            if (!t) r.fail(where, show(*arr->get(k)), "a table {N = .., phi = .., rate = ..}");
            r.only_keys(*t, where, {"N", "phi", "rate", "seeds"});
            for (const char* key : {"N", "phi", "rate"})
                if (!t->get(key) && (uses_rate || std::string(key) != "rate"))
                    r.fail(where + " " + key, "(missing)", "required in a point");
            const toml::node* rate = t->get("rate");
            points.push_back({r.integer(*t->get("N"), where + " N"),
                              sweep_number(*t->get("phi"), where + " phi", "phi"),
                              rate ? sweep_number(*rate, where + " rate", "rate") : 0.0,
                              {},
                              where});
            // A point's own seeds (a list; e.g. a merged campaign's replicas), instead of the
            // sweep's.
            if (const toml::node* own = t->get("seeds")) {
                const toml::array* list = own->as_array();
                if (!list || list->empty() || list->size() > static_cast<std::size_t>(max_replicas))
                    r.fail(where + " seeds", show(*own), "a non-empty list of seeds, e.g. [1, 4]");
                for (std::size_t j = 0; j < list->size(); ++j) {
                    const std::string at = where + " seeds[" + std::to_string(j) + "]";
                    const auto v = r.integer(*list->get(j), at);
                    if (v < 0) r.fail(at, show(*list->get(j)), "a seed >= 0");
                    points.back().seeds.push_back(static_cast<std::uint64_t>(v));
                }
            }
        }
    }
}

/// A rank's memory per replica of a campaign, before any runs: its parameters, its identity
/// and its row of the dry run's plan (measured: the peak resident memory of `jamsim run
/// --dry-run` rose by 1.35 kB per replica from 10^5 to 10^6 seeds).
constexpr double kSpecBytesPerReplica = 1.5e3;

/// One replica per point and seed, each validated.
void make_replicas(const Reader& r, const std::vector<Point>& points, Seeds seeds_read, const ReplicaParams& base,
                   std::int64_t max_replicas, int memory_ranks, CampaignSpec& spec) {
    std::vector<std::uint64_t>& seeds = seeds_read.listed;
    const std::int64_t seed_count = seeds_read.count;
    if (points.empty())
        throw SpecError(r.path() +
                        ": [sweep] makes no replica: give it N, phi and rate lists, or points = [...], or both");
    // The sweep's size, before a replica is made: a typo (seeds = 10000000) must not fill
    // the memory of every rank.
    const double seeds_per_point = seed_count > 0 ? static_cast<double>(seed_count) : static_cast<double>(seeds.size());
    double replica_count = 0.0;
    for (const Point& pt : points)
        replica_count += pt.seeds.empty() ? seeds_per_point : static_cast<double>(pt.seeds.size());
    if (replica_count > static_cast<double>(max_replicas))
        r.fail("[sweep]",
               show_value(replica_count) + " replicas (" + std::to_string(points.size()) + " points x " +
                   show_value(seeds_per_point) + " seeds)",
               "at most " + std::to_string(max_replicas) +
                   " replicas per campaign (jamsim run --max-replicas raises the cap; each replica "
                   "costs every rank about 1 kB of memory before it runs)");
    // Under the cap, the node's memory: every rank holds the whole campaign.
    if (const double needed = replica_count * kSpecBytesPerReplica * memory_ranks, available = available_memory();
        memory_ranks > 0 && std::isfinite(available) && needed > kMemoryMargin * available)
        r.fail("[sweep]",
               show_value(replica_count) + " replicas (" + std::to_string(points.size()) + " points x " +
                   show_value(seeds_per_point) + " seeds)",
               "a campaign this node's memory holds: its description alone takes about " +
                   show_bytes(replica_count * kSpecBytesPerReplica) + " on every rank (about " +
                   show_bytes(kSpecBytesPerReplica) + " per replica; " + std::to_string(memory_ranks) +
                   (memory_ranks == 1 ? " rank" : " ranks") + " on this node: " + show_bytes(needed) +
                   "), and this node has " + show_bytes(available) +
                   " available (jamsim plans for 80% of it); split the campaign into smaller ones");
    for (std::int64_t k = 1; k <= seed_count; ++k) seeds.push_back(static_cast<std::uint64_t>(k));

    for (const Point& pt : points)
        for (std::uint64_t seed : pt.seeds.empty() ? seeds : pt.seeds) {
            ReplicaParams p = base;
            p.n = pt.n;
            p.phi = pt.phi;
            p.rate = pt.rate == 0.0 ? 0.0 : pt.rate;  // -0 is 0 (it made a replica of its own)
            p.seed = seed;
            const auto errors = validate(p);
            if (!errors.empty()) {
                const auto& e = errors.front();
                const ParamInfo* info = find_parameter(e.key);
                // A listed point's own N, phi, rate or seeds are named where they are written.
                const bool own = !pt.where.empty() && (e.key == "N" || e.key == "phi" || e.key == "rate" ||
                                                       (e.key == "seed" && !pt.seeds.empty()));
                r.fail(own    ? pt.where + " " + (e.key == "seed" ? "seeds" : e.key)
                       : info ? location(*info)
                              : e.key,
                       e.value, e.allowed);
            }
            spec.replicas.push_back(p);
        }
}

/// Two values of phi or rate closer than this (relative) are one state point written twice
/// (a generated list's rounding: 0.84 and 0.8400000000000001), not two.
constexpr double kSameValue = 1e-12;

/// Values of `key` (phi or rate) over the sweep's replicas that are distinct but closer than
/// kSameValue: refused, naming both (they print alike and the analysis would split their seeds).
void check_values_apart(const Reader& r, const CampaignSpec& spec, const std::string& key,
                        double ReplicaParams::*value) {
    std::set<double> values;
    for (const ReplicaParams& p : spec.replicas)
        if (std::isfinite(p.*value)) values.insert(p.*value);
    for (auto it = values.begin(); it != values.end() && std::next(it) != values.end(); ++it) {
        const double a = *it, b = *std::next(it);
        if (b - a > kSameValue * std::max(std::abs(a), std::abs(b))) continue;
        char gap[32];
        std::snprintf(gap, sizeof gap, "%.2g", (b - a) / std::max(std::abs(a), std::abs(b)));
        throw SpecError(r.path() + ": [sweep] " + key + " holds " + show_value(a) + " and " + show_value(b) +
                        ", which is not allowed: values at least 1e-12 apart, relative (these differ by " + gap +
                        ": one state point written twice, as a generated list's rounding makes it; write it once)");
    }
}

/// The same replica twice would compute the same bits twice: a value listed twice in a sweep
/// list, or a point that repeats the grid or another point.
void check_each_once(const Reader& r, const CampaignSpec& spec) {
    check_values_apart(r, spec, "phi", &ReplicaParams::phi);
    check_values_apart(r, spec, "rate", &ReplicaParams::rate);
    {
        std::unordered_map<std::string, std::size_t> seen;
        for (std::size_t k = 0; k < spec.replicas.size(); ++k) {
            const ReplicaParams& p = spec.replicas[k];
            const auto [it, fresh] = seen.emplace(describe(p), k);
            if (fresh) continue;
            throw SpecError(r.path() + ": [sweep] makes the replica N = " + std::to_string(p.n) +
                            ", phi = " + show_value(p.phi) + ", rate = " + show_value(p.rate) +
                            ", seed = " + std::to_string(p.seed) + " twice (replicas " + std::to_string(it->second) +
                            " and " + std::to_string(k) +
                            "), which is not allowed: each replica once (a seed, N, phi or rate listed twice, or a "
                            "point that repeats the grid or another point); list each value once");
        }
    }
}

/// Rate ladders: for each (N, phi, seed) the replicas in order of decreasing rate, each
/// starting from the end state of the one before (its predecessor; ladder_from = its rate).
void link_rate_ladders(const Reader& r, CampaignSpec& spec) {
    std::map<std::tuple<std::int64_t, double, std::uint64_t>, std::vector<std::size_t>> chains;
    for (std::size_t k = 0; k < spec.replicas.size(); ++k) {
        const ReplicaParams& p = spec.replicas[k];
        chains[{p.n, p.phi, p.seed}].push_back(k);
    }
    spec.predecessor.assign(spec.replicas.size(), -1);
    for (auto& [key, chain] : chains) {
        std::stable_sort(chain.begin(), chain.end(),
                         [&](std::size_t a, std::size_t b) { return spec.replicas[a].rate > spec.replicas[b].rate; });
        const auto& [n, phi, seed] = key;
        const std::string which =
            "N = " + std::to_string(n) + ", phi = " + show_value(phi) + ", seed = " + std::to_string(seed);
        if (chain.size() < 2)
            r.fail("[sweep] rate_ladder", "\"down\"",
                   "at least two rates for each N, phi and seed (" + which + " has one)");
        for (std::size_t k = 0; k < chain.size(); ++k) {
            ReplicaParams& p = spec.replicas[chain[k]];
            if (!(p.rate > 0.0)) r.fail("[sweep] rate", show_value(p.rate), "rates > 0 in a rate ladder");
            if (k == 0) continue;
            const ReplicaParams& before = spec.replicas[chain[k - 1]];
            if (before.rate == p.rate)
                r.fail("[sweep] rate", show_value(p.rate),
                       "distinct rates in a rate ladder (" + which + " has it twice)");
            p.ladder_from = before.rate;
            spec.predecessor[chain[k]] = static_cast<std::int64_t>(chain[k - 1]);
        }
    }
}

}  // namespace

void expand_sweep(const Reader& r, const toml::table& sweep, ReplicaParams base, std::int64_t max_replicas,
                  int memory_ranks, CampaignSpec& spec) {
    const Seeds seeds = read_seeds(r, sweep);
    // Models without a shear rate (the minimisation protocols) take rate 0; a sweep may say
    // so explicitly (rate = [0]) but not ask for another rate.
    ReplicaParams rate_probe = base;
    const bool uses_rate = (rate_probe.rate = 1.0, uses_parameter(rate_probe, "rate"));
    if (!uses_rate) base.rate = 0.0;
    const SweepNumbers sweep_number(r, base, uses_rate);
    std::vector<Point> points;
    read_grid(r, sweep, sweep_number, uses_rate, max_replicas, points);
    read_points(r, sweep, sweep_number, uses_rate, max_replicas, points);
    make_replicas(r, points, seeds, base, max_replicas, memory_ranks, spec);
    check_each_once(r, spec);
    if (!base.rate_ladder.empty()) link_rate_ladders(r, spec);
}

}  // namespace jamsim::spec_detail

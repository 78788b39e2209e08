#include "jamsim/spec/campaign_spec.hpp"

#include <algorithm>

#include "jamsim/run/model_registry.hpp"

#include <toml++/toml.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <set>
#include <sstream>
#include <cstdio>

namespace jamsim {

namespace {

/// Text with its NUL characters written as TOML writes them (\u0000), so that a message
/// shows them instead of ending there.
std::string printable(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '\0')
            out += "\\u0000";
        else
            out.push_back(c);
    }
    return out;
}

std::string show(const toml::node& node) {
    std::ostringstream os;
    if (auto s = node.as_string())
        os << '"' << printable(s->get()) << '"';
    else if (node.is_table())
        os << "{...}";
    else if (auto a = node.as_array()) {
        os << '[';
        for (std::size_t k = 0; k < a->size(); ++k) os << (k ? ", " : "") << show(*a->get(k));
        os << ']';
    } else if (auto i = node.value<std::int64_t>(); i && node.is_integer())
        os << *i;
    else if (auto d = node.value<double>())
        os << *d;
    else if (auto b = node.value<bool>())
        os << (*b ? "true" : "false");
    else
        os << "(value)";
    return os.str();
}

/// Reads typed values out of the parsed document and reports problems with their location.
class Reader {
  public:
    explicit Reader(const std::string& path) : path_(path) {}

    [[noreturn]] void fail(const std::string& where, const std::string& value, const std::string& allowed) const {
        throw SpecError(path_ + ": " + where + " = " + value + " is not allowed: " + allowed);
    }

    /// Every key of `table` must be in `allowed` (so a typo is never ignored).
    void only_keys(const toml::table& table, const std::string& name, const std::set<std::string>& allowed) const {
        for (auto&& [key, node] : table) {
            if (allowed.count(std::string(key.str()))) continue;
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail((name.empty() ? "" : name + " ") + printable(std::string(key.str())), show(node),
                 "unknown key; known keys in " + (name.empty() ? "the top level" : name) + ": " + list);
        }
    }

    const toml::table* table(const toml::table& root, const std::string& name) const {
        const toml::node* node = root.get(name);
        if (!node) return nullptr;
        if (!node->is_table()) fail(name, show(*node), "a table [" + name + "]");
        return node->as_table();
    }

    double number(const toml::table& t, const std::string& where, const std::string& key, double fallback) const {
        const toml::node* node = t.get(key);
        if (!node) return fallback;
        if (auto v = node->value<double>(); v && (node->is_floating_point() || node->is_integer())) return *v;
        fail(where + " " + key, show(*node), "a number");
    }

    std::int64_t integer(const toml::node& node, const std::string& where) const {
        if (auto v = node.value<std::int64_t>(); v && node.is_integer()) return *v;
        fail(where, show(node), "an integer");
    }

    std::string string(const toml::table& t, const std::string& where, const std::string& key,
                       const std::string& fallback, bool required = false) const {
        const toml::node* node = t.get(key);
        if (!node) {
            if (required) fail(where + " " + key, "(missing)", "a string (required)");
            return fallback;
        }
        if (auto s = node->as_string()) {
            no_nul(s->get(), where + " " + key, *node);
            return s->get();
        }
        fail(where + " " + key, show(*node), "a string");
    }

    /// A NUL character would silently end the string where it is stored (HDF5 attributes,
    /// file names, C strings): refuse it.
    void no_nul(const std::string& text, const std::string& where, const toml::node& node) const {
        if (text.find('\0') != std::string::npos) fail(where, show(node), "a string without NUL characters (\\u0000)");
    }

    template <class F> void each(const toml::table& t, const std::string& where, const std::string& key, F&& f) const {
        const toml::node* node = t.get(key);
        if (!node) fail(where + " " + key, "(missing)", "a non-empty list");
        const toml::array* arr = node->as_array();
        if (!arr) {
            f(*node, where + " " + key);
            return;
        }
        if (arr->empty()) fail(where + " " + key, "[]", "a non-empty list");
        for (std::size_t k = 0; k < arr->size(); ++k)
            f(*arr->get(k), where + " " + key + "[" + std::to_string(k) + "]");
    }

    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

struct Point {
    std::int64_t n;
    double phi, rate;
    std::vector<std::uint64_t> seeds;  ///< its own seeds (a point's `seeds`); empty: the sweep's
};

/// Named potentials of [potential] name: presets of the exponent alpha.
constexpr std::pair<std::string_view, double> kNamedPotentials[] = {{"harmonic", 2.0}, {"hertzian", 2.5}};

/// Where a parameter is written in a campaign file, for messages: "[sweep] phi".
std::string location(const ParamInfo& info) {
    std::string out = "[";
    out.append(info.table).append("] ").append(info.toml_key);
    return out;
}

/// A TOML scalar as a parameter value (nullopt for tables, arrays, booleans, dates).
std::optional<ParamValue> scalar(const toml::node& node) {
    if (auto s = node.as_string()) return ParamValue{s->get()};
    if (node.is_integer()) return ParamValue{*node.value<std::int64_t>()};
    if (node.is_floating_point()) return ParamValue{*node.value<double>()};
    return std::nullopt;
}

std::string kind_of(const ParamInfo& info) {
    if (!is_numeric(info)) return "a string";
    return std::holds_alternative<double ReplicaParams::*>(info.field) ? "a number" : "an integer";
}

/// Set one parameter from a node, or fail naming where it was written.
void read_into(const Reader& r, ReplicaParams& p, const ParamInfo& info, const toml::node& node,
               const std::string& where) {
    const auto value = scalar(node);
    if (!value || !set_value(p, info, *value)) r.fail(where, show(node), kind_of(info));
    if (const auto* text = std::get_if<std::string>(&*value)) r.no_nul(*text, where, node);
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

CampaignSpec parse_campaign(const std::string& text, const std::string& path, std::int64_t max_replicas) {
    const Reader r(path);
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << path << ":" << e.source().begin.line << ":" << e.source().begin.column
           << ": malformed TOML: " << e.description();
        throw SpecError(os.str());
    }
    const std::set<std::string> tables{"campaign", "model", "potential", "system", "run", "sweep"};
    r.only_keys(root, "", tables);
    const auto* campaign = r.table(root, "campaign");
    if (!campaign) r.fail("[campaign]", "(missing)", "a [campaign] table with name and output");
    const auto* sweep = r.table(root, "sweep");
    if (!sweep) r.fail("[sweep]", "(missing)", "a [sweep] table");
    r.only_keys(*campaign, "[campaign]", {"name", "output"});

    CampaignSpec spec;
    spec.path = path;
    spec.text = text;
    spec.name = r.string(*campaign, "[campaign]", "name", "", true);
    spec.output = r.string(*campaign, "[campaign]", "output", "", true);
    if (spec.name.empty()) r.fail("[campaign] name", "\"\"", "a non-empty string");
    if (spec.output.empty()) r.fail("[campaign] output", "\"\"", "a non-empty path");
    spec.run_table = r.table(root, "run") != nullptr;

    // Every key of every table must be a parameter of that table (so a typo is never
    // ignored); the model's name comes first, since it decides which parameters apply.
    ReplicaParams base;
    const toml::table empty;
    std::vector<std::pair<const ParamInfo*, std::string>> given;  // parameters set, for the use check
    for (const std::string table : {"model", "potential", "system", "run", "sweep"}) {
        const toml::table* t = r.table(root, table);
        std::set<std::string> keys;
        for (const auto& info : parameters())
            if (info.table == table) keys.insert(std::string(info.toml_key));
        if (table == "potential") keys.insert("name");
        if (table == "sweep") keys.insert("points");
        r.only_keys(t ? *t : empty, "[" + table + "]", keys);
        if (!t) continue;
        for (const auto& info : parameters()) {
            if (info.table != table) continue;
            if (table == "sweep" && (info.key == "N" || info.key == "phi" || info.key == "rate" || info.key == "seed"))
                continue;  // the sweep's axes, expanded below
            if (const toml::node* node = t->get(info.toml_key)) {
                read_into(r, base, info, *node, location(info));
                given.emplace_back(&info, show(*node));
            }
        }
    }
    if (!find_model(base.model)) r.fail("[model] name", base.model, "one of: " + model_list());
    if (const toml::table* pot = r.table(root, "potential")) {
        const std::string name = r.string(*pot, "[potential]", "name", "");
        if (!name.empty() && pot->get("alpha"))
            r.fail("[potential] alpha", show(*pot->get("alpha")), "either name or alpha, not both");
        if (!name.empty()) {
            const auto* named = std::find_if(std::begin(kNamedPotentials), std::end(kNamedPotentials),
                                             [&](const auto& e) { return e.first == name; });
            if (named == std::end(kNamedPotentials))
                r.fail("[potential] name", "\"" + name + "\"", "\"harmonic\" or \"hertzian\"");
            base.alpha = named->second;
        }
    }
    for (const auto& [info, shown] : given)
        // frame_interval = 0 (no frames, the default) may be written for any model.
        if (!uses_parameter(base, info->key) && !(info->key == "frame_interval" && base.frame_interval == 0.0)) {
            std::string users;
            for (const auto& m : models()) {
                ReplicaParams q = base;
                q.model = std::string(m.name);
                q.rate = info->key == "time" ? 0.0 : 1.0;  // the run length follows the rate
                if (uses_parameter(q, info->key)) users += (users.empty() ? "" : ", ") + q.model;
            }
            // Keys whose use follows another setting, not the model: say which setting.
            if (info->key == "initial_match")
                r.fail(location(*info), shown,
                       "initial_match only with [run] initial (it says which replica of "
                       "that source starts each replica; without a source there is none)");
            if (info->key == "time" && base.rate > 0.0)
                r.fail(location(*info), shown,
                       "time only at rate = 0 (dynamics without shear); at rate > 0 the run "
                       "length is strain (" +
                           base.model + " takes strain here)");
            r.fail(location(*info), shown,
                   base.model + " does not use " + std::string(info->key) +
                       " (used by: " + (users.empty() ? "none" : users) + ")");
        }

    std::vector<std::uint64_t> seeds;
    std::int64_t seed_count = 0;  // seeds = K: seeds 1..K (listed once the sweep's size is checked)
    if (const toml::node* s = sweep->get("seeds"); s && !s->is_array()) {
        seed_count = r.integer(*s, "[sweep] seeds");
        if (seed_count < 1) r.fail("[sweep] seeds", show(*s), "a count >= 1 or a list of seeds");
    } else if (s) {
        r.each(*sweep, "[sweep]", "seeds", [&](const toml::node& n, const std::string& where) {
            const auto v = r.integer(n, where);
            if (v < 0) r.fail(where, show(n), "a seed >= 0");
            seeds.push_back(static_cast<std::uint64_t>(v));
        });
    } else {
        seeds.push_back(1);
    }

    // Models without a shear rate (the minimisation protocols) take rate 0; a sweep may say
    // so explicitly (rate = [0]) but not ask for another rate.
    ReplicaParams rate_probe = base;
    const bool uses_rate = (rate_probe.rate = 1.0, uses_parameter(rate_probe, "rate"));
    if (!uses_rate) base.rate = 0.0;
    auto sweep_number = [&](const toml::node& n, const std::string& where, const char* key) {
        const auto v = n.value<double>();
        if (!v || !(n.is_floating_point() || n.is_integer())) r.fail(where, show(n), "a number");
        if (std::string(key) == "rate" && !uses_rate && *v != 0.0)
            r.fail(where, show(n), "0 or no rate: " + base.model + " does not use a shear rate");
        return *v;
    };
    std::vector<Point> points;
    const bool grid = sweep->get("N") || sweep->get("phi") || sweep->get("rate");
    if (grid) {
        std::vector<std::int64_t> ns;
        std::vector<double> phis, rates;
        r.each(*sweep, "[sweep]", "N",
               [&](const toml::node& n, const std::string& w) { ns.push_back(r.integer(n, w)); });
        r.each(*sweep, "[sweep]", "phi",
               [&](const toml::node& n, const std::string& w) { phis.push_back(sweep_number(n, w, "phi")); });
        if (uses_rate || sweep->get("rate"))
            r.each(*sweep, "[sweep]", "rate",
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
                for (double rate : rates) points.push_back({n, phi, rate, {}});
    }
    if (const toml::node* p = sweep->get("points")) {
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
                              {}});
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
    if (points.empty()) r.fail("[sweep]", "{}", "N, phi and rate lists, or points = [...], or both");
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
    for (std::int64_t k = 1; k <= seed_count; ++k) seeds.push_back(static_cast<std::uint64_t>(k));

    for (const Point& pt : points)
        for (std::uint64_t seed : pt.seeds.empty() ? seeds : pt.seeds) {
            ReplicaParams p = base;
            p.n = pt.n;
            p.phi = pt.phi;
            p.rate = pt.rate;
            p.seed = seed;
            const auto errors = validate(p);
            if (!errors.empty()) {
                const auto& e = errors.front();
                const ParamInfo* info = find_parameter(e.key);
                r.fail(info ? location(*info) : e.key, e.value, e.allowed);
            }
            spec.replicas.push_back(p);
        }
    // The same replica twice would compute the same bits twice: a value listed twice in a
    // sweep list, or a point that repeats the grid or another point.
    {
        std::unordered_map<std::string, std::size_t> seen;
        for (std::size_t k = 0; k < spec.replicas.size(); ++k) {
            const ReplicaParams& p = spec.replicas[k];
            const auto [it, fresh] = seen.emplace(describe(p), k);
            if (fresh) continue;
            r.fail("[sweep]",
                   "N = " + std::to_string(p.n) + ", phi = " + show_value(p.phi) + ", rate = " + show_value(p.rate) +
                       ", seed = " + std::to_string(p.seed),
                   "each replica once: replicas " + std::to_string(it->second) + " and " + std::to_string(k) +
                       " are the same (a seed, N, phi or rate listed twice, or a point that repeats the grid "
                       "or another point); list each value once");
        }
    }
    if (!base.rate_ladder.empty()) link_rate_ladders(r, spec);
    // A checkpoint interval asked for that no replica reaches would never checkpoint.
    if (const toml::table* run_table = r.table(root, "run"); run_table && run_table->get("checkpoint_steps")) {
        std::int64_t longest = 0;
        for (const auto& p : spec.replicas)
            if (uses_parameter(p, "checkpoint_steps")) longest = std::max(longest, checkpointed_steps(p));
        if (longest > 0 && base.checkpoint_steps > longest)
            r.fail("[run] checkpoint_steps", std::to_string(base.checkpoint_steps),
                   "at most the longest replica's " + std::to_string(longest) +
                       " steps (a longer interval never checkpoints)");
    }
    return spec;
}

CampaignSpec load_campaign(const std::string& path, std::int64_t max_replicas) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (!fs::exists(st)) {
        std::error_code link_ec;
        if (fs::is_symlink(fs::symlink_status(path, link_ec)))  // a dangling link or a loop of links
            throw SpecError(path + ": a symbolic link that leads to no campaign file (" +
                            (ec.value() == ELOOP ? std::string("a loop of links")
                                                 : "it names '" + fs::read_symlink(path, link_ec).string() +
                                                       "', which does not exist") +
                            ")");
        throw SpecError(path + ": no such campaign file");
    }
    if (fs::is_directory(st)) throw SpecError(path + ": is a directory, not a campaign file (a TOML file)");
    if (!fs::is_regular_file(st)) throw SpecError(path + ": is not a regular file, not a campaign file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SpecError(path + ": cannot read the campaign file");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_campaign(text.str(), path, max_replicas);
}

std::vector<std::string> campaign_warnings(const CampaignSpec& spec) {
    std::vector<std::pair<std::string, std::string>> first;  // kind, text of its first replica
    std::vector<std::size_t> count;
    for (const ReplicaParams& p : spec.replicas)
        for (auto& [kind, text] : advisories(p)) {
            std::size_t k = 0;
            while (k < first.size() && first[k].first != kind) ++k;
            if (k == first.size()) {
                first.emplace_back(kind, text);
                count.push_back(0);
            }
            ++count[k];
        }
    std::vector<std::string> out;
    for (std::size_t k = 0; k < first.size(); ++k) {
        std::string line = first[k].second;
        if (count[k] > 1) line.append(" (and ").append(std::to_string(count[k] - 1)).append(" more replicas alike)");
        out.push_back(line);
    }
    return out;
}

std::string settings_difference(const CampaignSpec& a, const CampaignSpec& b, const std::string& a_label,
                                const std::string& b_label) {
    std::vector<std::string> out;
    const auto quoted = [](const ParamValue& v) {
        std::string text = show_value(v);
        if (std::holds_alternative<std::string>(v)) {
            text.insert(text.begin(), '"');
            text.push_back('"');
        }
        return text;
    };
    if (a.name != b.name)
        out.push_back("[campaign] name: " + a_label + " " + quoted(a.name) + ", " + b_label + " " + quoted(b.name));
    // Every replica of a campaign has its settings (its first one stands for all); the
    // sweep's axes and the derived ladder_from are what may differ.
    const ReplicaParams& pa = a.replicas.front();
    const ReplicaParams& pb = b.replicas.front();
    for (const auto& info : parameters()) {
        if (info.table.empty() || info.key == "N" || info.key == "phi" || info.key == "rate" || info.key == "seed")
            continue;
        const ParamValue va = get_value(pa, info), vb = get_value(pb, info);
        if (va == vb) continue;
        out.push_back(location(info) + ": " + a_label + " " + quoted(va) + ", " + b_label + " " + quoted(vb));
    }
    std::string joined;
    for (const auto& line : out) joined += (joined.empty() ? "" : "; ") + line;
    return joined;
}

namespace {
/// A TOML basic string.
std::string toml_string(const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
        if (c == '"' || c == '\\') out.push_back('\\');
        if (static_cast<unsigned char>(c) < 0x20) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
            out += buf;
            continue;
        }
        out.push_back(c);
    }
    return out + "\"";
}

std::string toml_value(const ParamValue& v) {
    if (const auto* text = std::get_if<std::string>(&v)) return toml_string(*text);
    return show_value(v);
}
}  // namespace

std::string campaign_text(const std::string& name, const std::string& output,
                          const std::vector<ReplicaParams>& replicas, const std::string& comment) {
    std::string out;
    std::istringstream lines(comment);
    for (std::string line; std::getline(lines, line);) out += "# " + line + "\n";
    out += "[campaign]\nname = " + toml_string(name) + "\noutput = " + toml_string(output) + "\n";
    const ReplicaParams& base = replicas.front();
    const ReplicaParams defaults;
    for (const std::string table : {"model", "potential", "system", "run", "sweep"}) {
        out += "[" + table + "]\n";
        for (const auto& info : parameters()) {
            if (info.table != table || info.key == "N" || info.key == "phi" || info.key == "rate" || info.key == "seed")
                continue;
            const ParamValue value = get_value(base, info);
            if (info.key != "model" && value == get_value(defaults, info)) continue;
            if (std::none_of(replicas.begin(), replicas.end(),
                             [&](const ReplicaParams& p) { return uses_parameter(p, info.key); }))
                continue;
            out += std::string(info.toml_key) + " = " + toml_value(value) + "\n";
        }
    }
    std::map<std::tuple<std::int64_t, double, double>, std::set<std::uint64_t>> points;
    for (const ReplicaParams& p : replicas) points[{p.n, p.phi, p.rate}].insert(p.seed);
    out += "points = [\n";
    for (const auto& [point, seeds] : points) {
        const auto& [n, phi, rate] = point;
        out += "  {N = " + std::to_string(n) + ", phi = " + show_value(phi) + ", rate = " + show_value(rate) +
               ", seeds = [";
        bool first = true;
        for (const std::uint64_t seed : seeds) {
            out += (first ? "" : ", ") + std::to_string(seed);
            first = false;
        }
        out += "]},\n";
    }
    return out + "]\n";
}

std::string fingerprint(const CampaignSpec& spec) {
    // The version names what the results mean: v5 keyed every random number by the replica's
    // identity (its physical parameters and seed) instead of its position in the sweep, and
    // records only the parameters a model uses; v6 drops the kernel caches at checkpoint steps;
    // v7 has checkpoint steps in every minimisation protocol and archive layout 4.
    std::string out = "jamsim campaign v7 " + spec.name + " replicas " + std::to_string(spec.replicas.size()) + '\n';
    for (std::size_t k = 0; k < spec.replicas.size(); ++k)
        out += std::to_string(k) + ' ' + describe(spec.replicas[k]) + '\n';
    return out;
}

}  // namespace jamsim

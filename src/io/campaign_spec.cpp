#include "jamsim/io/campaign_spec.hpp"

#include <algorithm>

#include <toml++/toml.h>

#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace jamsim {

namespace {

std::string show(const toml::node& node) {
    std::ostringstream os;
    if (auto s = node.as_string()) os << '"' << s->get() << '"';
    else if (node.is_table()) os << "{...}";
    else if (auto a = node.as_array()) {
        os << '[';
        for (std::size_t k = 0; k < a->size(); ++k) os << (k ? ", " : "") << show(*a->get(k));
        os << ']';
    }
    else if (auto i = node.value<std::int64_t>(); i && node.is_integer()) os << *i;
    else if (auto d = node.value<double>()) os << *d;
    else if (auto b = node.value<bool>()) os << (*b ? "true" : "false");
    else os << "(value)";
    return os.str();
}

/// Reads typed values out of the parsed document and reports problems with their location.
class Reader {
  public:
    explicit Reader(const std::string& path) : path_(path) {}

    [[noreturn]] void fail(const std::string& where, const std::string& value,
                           const std::string& allowed) const {
        throw SpecError(path_ + ": " + where + " = " + value + " is not allowed: " + allowed);
    }

    /// Every key of `table` must be in `allowed` (so a typo is never ignored).
    void only_keys(const toml::table& table, const std::string& name,
                   const std::set<std::string>& allowed) const {
        for (auto&& [key, node] : table) {
            if (allowed.count(std::string(key.str()))) continue;
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail((name.empty() ? "" : name + " ") + std::string(key.str()), show(node),
                 "unknown key; known keys in " + (name.empty() ? "the top level" : name) +
                     ": " + list);
        }
    }

    const toml::table* table(const toml::table& root, const std::string& name) const {
        const toml::node* node = root.get(name);
        if (!node) return nullptr;
        if (!node->is_table()) fail(name, show(*node), "a table [" + name + "]");
        return node->as_table();
    }

    double number(const toml::table& t, const std::string& where, const std::string& key,
                  double fallback) const {
        const toml::node* node = t.get(key);
        if (!node) return fallback;
        if (auto v = node->value<double>(); v && (node->is_floating_point() || node->is_integer()))
            return *v;
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
        if (auto s = node->as_string()) return s->get();
        fail(where + " " + key, show(*node), "a string");
    }

    template <class F> void each(const toml::table& t, const std::string& where,
                                 const std::string& key, F&& f) const {
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

/// Where each ReplicaParams key lives in the file, for messages.
const std::map<std::string, std::string> kKeyLocation = {
    {"model", "[model] name"},       {"N", "[sweep] N"},
    {"phi", "[sweep] phi"},          {"rate", "[sweep] rate"},
    {"strain", "[run] strain"},      {"time", "[run] time"},
    {"transient", "[run] transient"}, {"sample-interval", "[run] sample_interval"},
    {"dt", "[model] dt"},            {"alpha", "[potential] alpha"},
    {"size-ratio", "[system] size_ratio"}, {"skin", "[system] skin"},
    {"kd", "[model] kd"},             {"delta", "[model] delta"}, {"solver", "[model] solver"}, {"mass", "[model] mass"},
    {"minimizer", "[model] minimizer"}, {"strain-step", "[model] strain_step"},
    {"energy-floor", "[model] energy_floor"}, {"force-tol", "[model] force_tol"},
    {"force-tol-abs", "[model] force_tol_abs"}, {"phi-tol", "[model] phi_tol"},
    {"temperature", "[model] temperature"}, {"cooling-time", "[model] cooling_time"},
};

struct Point {
    std::int64_t n;
    double phi, rate;
};

} // namespace

CampaignSpec parse_campaign(const std::string& text, const std::string& path) {
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
    r.only_keys(root, "", {"campaign", "model", "potential", "system", "run", "sweep"});
    const toml::table empty;
    const auto* campaign = r.table(root, "campaign");
    if (!campaign) r.fail("[campaign]", "(missing)", "a [campaign] table with name and output");
    const auto& model = r.table(root, "model") ? *r.table(root, "model") : empty;
    const auto& pot = r.table(root, "potential") ? *r.table(root, "potential") : empty;
    const auto& system = r.table(root, "system") ? *r.table(root, "system") : empty;
    const auto& run = r.table(root, "run") ? *r.table(root, "run") : empty;
    const auto* sweep = r.table(root, "sweep");
    if (!sweep) r.fail("[sweep]", "(missing)", "a [sweep] table");
    r.only_keys(*campaign, "[campaign]", {"name", "output"});
    r.only_keys(model, "[model]", {"name", "integrator", "dt", "kd", "delta", "petsc_options", "solver", "mass",
                                   "minimizer", "strain_step", "energy_floor", "force_tol",
                                   "force_tol_abs", "phi_tol", "temperature", "cooling_time"});
    r.only_keys(pot, "[potential]", {"name", "alpha"});
    r.only_keys(system, "[system]", {"size_ratio", "skin"});
    r.only_keys(run, "[run]", {"transient", "strain", "time", "sample_interval"});
    r.only_keys(*sweep, "[sweep]", {"N", "phi", "rate", "seeds", "points"});

    CampaignSpec spec;
    spec.path = path;
    spec.text = text;
    spec.name = r.string(*campaign, "[campaign]", "name", "", true);
    spec.output = r.string(*campaign, "[campaign]", "output", "", true);
    if (spec.name.empty()) r.fail("[campaign] name", "\"\"", "a non-empty string");
    if (spec.output.empty()) r.fail("[campaign] output", "\"\"", "a non-empty path");

    ReplicaParams base;
    base.model = r.string(model, "[model]", "name", base.model);
    const std::string integ = r.string(model, "[model]", "integrator", "euler");
    try {
        base.integrator = integrator_from_string(integ);
    } catch (const std::invalid_argument&) {
        r.fail("[model] integrator", "\"" + integ + "\"", "\"euler\" or \"heun\"");
    }
    base.dt = r.number(model, "[model]", "dt", base.dt);
    base.kd = r.number(model, "[model]", "kd", base.kd);
    base.delta = r.number(model, "[model]", "delta", base.delta);
    base.petsc_options = r.string(model, "[model]", "petsc_options", "");
    base.solver = r.string(model, "[model]", "solver", base.solver);
    base.mass = r.number(model, "[model]", "mass", base.mass);
    base.minimizer = r.string(model, "[model]", "minimizer", base.minimizer);
    base.strain_step = r.number(model, "[model]", "strain_step", base.strain_step);
    base.energy_floor = r.number(model, "[model]", "energy_floor", base.energy_floor);
    base.force_tol = r.number(model, "[model]", "force_tol", base.force_tol);
    base.force_tol_abs = r.number(model, "[model]", "force_tol_abs", base.force_tol_abs);
    base.phi_tol = r.number(model, "[model]", "phi_tol", base.phi_tol);
    base.temperature = r.number(model, "[model]", "temperature", base.temperature);
    base.cooling_time = r.number(model, "[model]", "cooling_time", base.cooling_time);
    const std::string pot_name = r.string(pot, "[potential]", "name", "");
    if (!pot_name.empty() && pot.get("alpha"))
        r.fail("[potential] alpha", show(*pot.get("alpha")),
               "either name or alpha, not both");
    if (pot_name == "harmonic") base.alpha = 2.0;
    else if (pot_name == "hertzian") base.alpha = 2.5;
    else if (!pot_name.empty())
        r.fail("[potential] name", "\"" + pot_name + "\"", "\"harmonic\" or \"hertzian\"");
    base.alpha = r.number(pot, "[potential]", "alpha", base.alpha);
    base.size_ratio = r.number(system, "[system]", "size_ratio", base.size_ratio);
    base.skin = r.number(system, "[system]", "skin", base.skin);
    base.transient = r.number(run, "[run]", "transient", base.transient);
    base.strain = r.number(run, "[run]", "strain", base.strain);
    base.time = r.number(run, "[run]", "time", base.time);
    base.sample_interval = r.number(run, "[run]", "sample_interval", base.sample_interval);

    std::vector<std::uint64_t> seeds;
    if (const toml::node* s = sweep->get("seeds"); s && !s->is_array()) {
        const auto count = r.integer(*s, "[sweep] seeds");
        if (count < 1) r.fail("[sweep] seeds", show(*s), "a count >= 1 or a list of seeds");
        for (std::int64_t k = 1; k <= count; ++k) seeds.push_back(static_cast<std::uint64_t>(k));
    } else if (s) {
        r.each(*sweep, "[sweep]", "seeds", [&](const toml::node& n, const std::string& where) {
            const auto v = r.integer(n, where);
            if (v < 0) r.fail(where, show(n), "a seed >= 0");
            seeds.push_back(static_cast<std::uint64_t>(v));
        });
    } else {
        seeds.push_back(1);
    }

    std::vector<Point> points;
    const bool grid = sweep->get("N") || sweep->get("phi") || sweep->get("rate");
    if (grid) {
        std::vector<std::int64_t> ns;
        std::vector<double> phis, rates;
        r.each(*sweep, "[sweep]", "N",
               [&](const toml::node& n, const std::string& w) { ns.push_back(r.integer(n, w)); });
        auto numbers = [&](const std::string& key, std::vector<double>& out) {
            r.each(*sweep, "[sweep]", key, [&](const toml::node& n, const std::string& w) {
                if (auto v = n.value<double>(); v && (n.is_floating_point() || n.is_integer()))
                    out.push_back(*v);
                else
                    r.fail(w, show(n), "a number");
            });
        };
        numbers("phi", phis);
        numbers("rate", rates);
        for (auto n : ns)
            for (double phi : phis)
                for (double rate : rates) points.push_back({n, phi, rate});
    }
    if (const toml::node* p = sweep->get("points")) {
        const toml::array* arr = p->as_array();
        if (!arr) r.fail("[sweep] points", show(*p), "a list of {N = .., phi = .., rate = ..}");
        for (std::size_t k = 0; k < arr->size(); ++k) {
            const std::string where = "[sweep] points[" + std::to_string(k) + "]";
            const toml::table* t = arr->get(k)->as_table();
            if (!t) r.fail(where, show(*arr->get(k)), "a table {N = .., phi = .., rate = ..}");
            r.only_keys(*t, where, {"N", "phi", "rate"});
            for (const char* key : {"N", "phi", "rate"})
                if (!t->get(key)) r.fail(where + " " + key, "(missing)", "required in a point");
            points.push_back({r.integer(*t->get("N"), where + " N"),
                              r.number(*t, where, "phi", 0.0), r.number(*t, where, "rate", 0.0)});
        }
    }
    if (points.empty())
        r.fail("[sweep]", "{}", "N, phi and rate lists, or points = [...], or both");

    for (const Point& pt : points)
        for (std::uint64_t seed : seeds) {
            ReplicaParams p = base;
            p.n = pt.n;
            p.phi = pt.phi;
            p.rate = pt.rate;
            p.seed = seed;
            p.replica = static_cast<std::uint32_t>(spec.replicas.size());
            const auto errors = validate(p);
            if (!errors.empty()) {
                const auto& e = errors.front();
                const auto loc = kKeyLocation.find(e.key);
                r.fail(loc == kKeyLocation.end() ? e.key : loc->second, e.value, e.allowed);
            }
            spec.replicas.push_back(p);
        }
    return spec;
}

CampaignSpec load_campaign(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw SpecError(path + ": cannot read the campaign file");
    std::ostringstream text;
    text << in.rdbuf();
    return parse_campaign(text.str(), path);
}

std::string fingerprint(const CampaignSpec& spec) {
    std::ostringstream os;
    os.precision(17);
    // The version names what the results mean: v4 changed the minimisers (CG's β, the line
    // search) and so the static models' results; the dynamics' results are those of v3, so
    // their archives still resume.
    const bool minimises = std::any_of(spec.replicas.begin(), spec.replicas.end(),
                                       [](const ReplicaParams& p) { return is_static_model(p.model); });
    os << "jamsim campaign " << (minimises ? "v4 " : "v3 ") << spec.name << " replicas "
       << spec.replicas.size() << '\n';
    for (const auto& p : spec.replicas)
        os << p.replica << ' ' << p.model << ' ' << p.n << ' ' << p.phi << ' ' << p.rate << ' '
           << p.strain << ' ' << p.time << ' ' << p.transient << ' ' << p.sample_interval << ' '
           << p.dt << ' ' << p.alpha << ' ' << p.size_ratio << ' ' << p.skin << ' ' << p.kd
           << ' ' << to_string(p.integrator) << ' ' << p.seed << ' ' << p.delta << ' ' << p.solver << ' ' << p.mass << ' ' << p.minimizer << ' ' << p.strain_step << ' '
           << p.energy_floor << ' ' << p.force_tol << ' ' << p.force_tol_abs << ' ' << p.phi_tol
           << ' ' << p.temperature << ' ' << p.cooling_time
           << " [" << p.petsc_options << "]\n";
    return os.str();
}

double estimated_cost(const ReplicaParams& p) {
    // Minimisations: rough force evaluations (a RAND quench ~1e3, a φ_J search ~2e4, a QS
    // step ~1e2); only the order of replicas matters (longest first).
    if (p.model == "RAND") return static_cast<double>(p.n) * 1e3;
    if (p.model == "COMPRESS") return static_cast<double>(p.n) * 2e4;
    if (p.model == "SHEARED") return static_cast<double>(p.n) * (2e4 + 1e2 * (p.strain / p.strain_step));
    if (p.model == "COOL") return static_cast<double>(p.n) * (1e3 + p.cooling_time / p.dt);
    if (p.model == "COOL_COMPRESS") return static_cast<double>(p.n) * (2e4 + p.cooling_time / p.dt);
    if (p.model == "QS") return static_cast<double>(p.n) * 1e2 * (p.strain / p.strain_step);
    const Schedule s = schedule_of(p);
    return static_cast<double>(p.n) * static_cast<double>(s.steps) * evaluations_per_step(p);
}

std::int64_t sample_count(const ReplicaParams& p) {
    const Schedule s = schedule_of(p);
    return s.steps / s.sample_every + 1;
}

} // namespace jamsim

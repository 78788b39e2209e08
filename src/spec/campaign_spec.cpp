#include "jamsim/spec/campaign_spec.hpp"

#include <algorithm>

#include "jamsim/core/invisible_text.hpp"
#include "jamsim/core/parse_number.hpp"
#include "jamsim/run/model_registry.hpp"
#include "sweep.hpp"

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

using spec_detail::location;
using spec_detail::printable;
using spec_detail::Reader;
using spec_detail::show;

namespace {

/// Line `number` (from 1) of text, without its end of line; empty past the end.
std::string line_of(const std::string& text, std::size_t number) {
    std::size_t begin = 0;
    for (std::size_t k = 1; k < number && begin != std::string::npos; ++k) {
        begin = text.find('\n', begin);
        if (begin != std::string::npos) ++begin;
    }
    if (begin == std::string::npos || begin >= text.size()) return "";
    const std::size_t end = text.find_first_of("\r\n", begin);
    return text.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

/// The written text of values at line:column positions of a file: its line starts found once,
/// so that a file of many values is read in time linear in its size (each value's line found
/// afresh made 20000 zeros on one line take 9 s, and 200000 a quarter of an hour).
class SourceText {
  public:
    explicit SourceText(const std::string& text) : text_(text) {
        starts_.push_back(0);
        for (std::size_t k = 0; k < text.size(); ++k)
            if (text[k] == '\n') starts_.push_back(k + 1);
    }

    /// The text of the value at `at` (up to a separator): what the file wrote.
    std::string token_at(const toml::source_position& at) {
        if (at.line == 0 || at.line > starts_.size() || at.column == 0) return "";
        const std::size_t line = starts_[at.line - 1];
        // toml++ counts columns in characters (code points), not bytes: skip column - 1 of them.
        std::size_t begin = line;
        if (at.line != ascii_checked_) {
            ascii_checked_ = at.line;
            end_ = std::min(text_.find_first_of("\r\n", line), text_.size());
            ascii_ = std::all_of(text_.begin() + static_cast<std::ptrdiff_t>(line),
                                 text_.begin() + static_cast<std::ptrdiff_t>(end_),
                                 [](char c) { return (static_cast<unsigned char>(c) & 0x80) == 0; });
            walked_column_ = 1;
            walked_byte_ = line;
        }
        if (ascii_) {
            begin = line + (at.column - 1);
        } else {  // walk on from the last value of this line (toml++ reads a line left to right)
            if (at.column < walked_column_) {
                walked_column_ = 1;
                walked_byte_ = line;
            }
            for (; walked_column_ < at.column && walked_byte_ < end_; ++walked_column_) {
                ++walked_byte_;
                while (walked_byte_ < end_ && (static_cast<unsigned char>(text_[walked_byte_]) & 0xC0) == 0x80)
                    ++walked_byte_;
            }
            begin = walked_byte_;
        }
        if (begin >= end_) return "";
        const std::size_t stop = std::min(text_.find_first_of(" \t,]}#\r\n", begin), end_);
        return text_.substr(begin, stop - begin);
    }

  private:
    const std::string& text_;
    std::vector<std::size_t> starts_;  ///< byte offset of each line
    std::size_t ascii_checked_ = 0;    ///< the line `ascii_` and `end_` are of (0: none)
    std::size_t end_ = 0;              ///< where that line ends
    bool ascii_ = true;
    std::size_t walked_column_ = 1, walked_byte_ = 0;  ///< where the walk along a non-ASCII line stands
};

/// Refuses a float the file writes as non-zero that parsed to 0 (1e-400: toml++ takes it as
/// 0 without a word, where the command line refuses it). `where` names the key ("[sweep] phi").
void refuse_underflow(const Reader& r, SourceText& text, const toml::node& node, const std::string& where) {
    if (const auto* value = node.as_floating_point(); value && value->get() == 0.0) {
        const std::string written = text.token_at(node.source().begin);
        const std::string mantissa = written.substr(0, written.find_first_of("eE"));
        if (mantissa.find_first_of("123456789") != std::string::npos) r.fail(where, written, kDoubleRangeWords);
    } else if (const auto* array = node.as_array()) {
        for (const toml::node& item : *array) refuse_underflow(r, text, item, where);
    } else if (const auto* table = node.as_table()) {
        for (const auto& [key, item] : *table) {
            std::string inner = where;  // appended, not '+': GCC 12's -Wrestrict misfires on that here
            if (where.empty())
                inner.append("[").append(key.str()).append("]");
            else
                inner.append(" ").append(printable(std::string(key.str())));
            refuse_underflow(r, text, item, inner);
        }
    }
}

/// Named potentials of [potential] name: presets of the exponent alpha.
constexpr std::pair<std::string_view, double> kNamedPotentials[] = {{"harmonic", 2.0}, {"hertzian", 2.5}};

/// A TOML scalar as a parameter value (nullopt for tables, arrays, booleans, dates).
std::optional<ParamValue> scalar(const toml::node& node) {
    if (auto s = node.as_string()) return ParamValue{s->get()};
    if (node.is_integer()) return ParamValue{*node.value<std::int64_t>()};
    if (node.is_floating_point()) return ParamValue{*node.value<double>()};
    return std::nullopt;
}

/// Set one parameter from a node, or fail naming where it was written.
void read_into(const Reader& r, ReplicaParams& p, const ParamInfo& info, const toml::node& node,
               const std::string& where) {
    const auto value = scalar(node);
    if (!value || !set_value(p, info, *value)) r.fail(where, show(node), value_kind(info));
    if (const auto* text = std::get_if<std::string>(&*value)) r.no_nul(*text, where, node);
}

/// The first line (from 1) whose key or table header has more than `most` dotted parts, else
/// 0. toml++ descends once per part: 60000 of them overflowed the stack (a crash, not a
/// message), while its nesting of arrays and inline tables stops at 256. Counted on each line
/// up to its first '=', '#' or ',' (a key, a header, not a line of an array's values); quoted
/// parts with dots count too, which no campaign key has.
std::size_t deeply_dotted_line(const std::string& text, std::size_t most) {
    std::size_t line = 1, dots = 0;
    bool in_key = true;
    for (const char c : text) {
        if (c == '\n') {
            if (dots > most) return line;
            ++line;
            dots = 0;
            in_key = true;
        } else if (in_key && (c == '=' || c == '#' || c == ',')) {  // ',': a line of an array
            in_key = false;
        } else if (in_key && c == '.') {
            ++dots;
        }
    }
    return dots > most ? line : 0;
}

}  // namespace

CampaignSpec parse_campaign(const std::string& text, const std::string& path, std::int64_t max_replicas,
                            int memory_ranks) {
    const Reader r(path);
    if (text.rfind("\x89HDF\r\n\x1a\n", 0) == 0)  // toml++ said "invalid utf-8 sequence"
        throw SpecError(path + ": an HDF5 file (a campaign archive? jamsim status " + path +
                        " says what it is), not a campaign file (TOML text)");
    if (const std::size_t line = deeply_dotted_line(text, 256))
        throw SpecError(path + ":" + std::to_string(line) +
                        ": a key or table name of more than 256 dotted parts is not allowed (campaign keys have at "
                        "most 2)");
    toml::table root;
    try {
        root = toml::parse(text, path);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        std::string description(e.description());
        // toml++ names a quoted duplicate key garbled ('"N"N"'): quote the line instead.
        std::string line = printable(line_of(text, e.source().begin.line));
        if (line.size() > 160) {  // one line of a long array: its start names the key
            std::size_t cut = 160;
            while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;  // whole UTF-8
            line = line.substr(0, cut) + " ...";
        }
        if (description.find("cannot redefine existing") != std::string::npos)
            description = "a key or table defined a second time (TOML allows each once): '" + line + "'";
        else if (description.find("floating-point") != std::string::npos &&
                 (description.find("could not be interpreted") != std::string::npos ||
                  description.find("not representable") != std::string::npos))  // toml++ with charconv
            description += " (in '" + line + "': " + kDoubleRangeWords + " is allowed)";
        else if (!line.empty())  // toml++ names no key: the line does
            description += " (in '" + line + "')";
        os << path << ":" << e.source().begin.line << ":" << e.source().begin.column
           << ": malformed TOML: " << description;
        throw SpecError(os.str());
    }
    SourceText source(text);
    refuse_underflow(r, source, root, "");
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
    // A line break or other control character split every log line that names them, and made a
    // file name that shells and schedulers mangle.
    const auto has_control = [](const std::string& t) {
        return std::any_of(t.begin(), t.end(),
                           [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
    };
    if (has_control(spec.name))
        r.fail("[campaign] name", show(*campaign->get("name")), "a name without line breaks or control characters");
    // " x" and "x" read alike in every progress line and listing (and "   " as no name at all),
    // as the output's name does, which is refused so too.
    if (spec.name.front() == ' ' || spec.name.back() == ' ')
        r.fail("[campaign] name", show(*campaign->get("name")),
               "a name that neither starts nor ends with a space (a quoting mistake?)");
    // The name heads every progress line and is kept in the archive: a 5 MB name was taken.
    if (constexpr std::size_t most = 256; spec.name.size() > most)
        r.fail("[campaign] name",
               "\"" + spec.name.substr(0, 32) + "...\" (" + std::to_string(spec.name.size()) + " bytes)",
               "a name of at most " + std::to_string(most) + " bytes");
    if (has_control(spec.output))
        r.fail("[campaign] output", show(*campaign->get("output")), "a path without line breaks or control characters");
    // An invisible character (a zero-width space, a direction mark) makes two names or paths
    // that read the same in every log, status line and listing differ.
    for (const auto& [key, value] : {std::pair{"name", &spec.name}, std::pair{"output", &spec.output}})
        if (const std::string code = invisible_character(*value); !code.empty())
            r.fail(std::string("[campaign] ") + key, show(*campaign->get(key)),
                   std::string("a ") + (key == std::string("name") ? "name" : "path") +
                       " without invisible characters (it holds " + code + ")");
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
    if (!find_model(base.model)) r.fail("[model] name", show_in_message(base.model), "one of: " + model_list());
    if (const toml::table* pot = r.table(root, "potential")) {
        const std::string name = r.string(*pot, "[potential]", "name", "");
        if (name.empty() && pot->get("name"))  // name = "" was taken as the default, harmonic
            r.fail("[potential] name", "\"\"", "\"harmonic\" or \"hertzian\" (or no name, with alpha)");
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
    // The run length's keys follow each replica's rate (strain at rate > 0, time at rate 0),
    // which the sweep sets: they are checked against the replicas, after it.
    const auto follows_rate = [&](const ParamInfo& info) {
        return (info.key == "strain" || info.key == "time") && model_of(base).kind == ModelKind::Dynamics;
    };
    // Keys whose default means "none" may be written with it for any model (TEMPLATE.toml
    // lists them so): frame_interval = 0 (no frames), initial = "" (random positions),
    // rate_ladder = "" (no ladder).
    const auto written_as_none = [&](const ParamInfo& info) {
        return (info.key == "frame_interval" && base.frame_interval == 0.0) ||
               (info.key == "initial" && base.initial.empty()) ||
               (info.key == "rate_ladder" && base.rate_ladder.empty());
    };
    for (const auto& [info, shown] : given)
        if (!follows_rate(*info) && !uses_parameter(base, info->key) && !written_as_none(*info)) {
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
            r.fail(location(*info), shown,
                   base.model + " does not use " + std::string(info->key) +
                       " (used by: " + (users.empty() ? "none" : users) + ")");
        }

    expand_sweep(r, *sweep, base, max_replicas, memory_ranks, spec);
    for (const auto& [info, shown] : given) {
        if (!follows_rate(*info)) continue;
        // (the key named, not the binding: Clang before 16 cannot capture a structured binding)
        const auto key = info->key;
        const bool used = std::any_of(spec.replicas.begin(), spec.replicas.end(),
                                      [&](const ReplicaParams& p) { return uses_parameter(p, key); });
        if (used) continue;
        if (info->key == "time")
            r.fail(location(*info), shown,
                   "time only at rate = 0 (dynamics without shear); every rate of this sweep is > 0, "
                   "so the run length is strain (" +
                       base.model + " takes strain here)");
        r.fail(location(*info), shown,
               "strain only at rate > 0; every rate of this sweep is 0, so the run length is time (" + base.model +
                   " takes time here)");
    }
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

CampaignSpec load_campaign(const std::string& path, std::int64_t max_replicas, int memory_ranks) {
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
    return parse_campaign(text.str(), path, max_replicas, memory_ranks);
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

#pragma once
// Reading a campaign file's TOML with messages that name the file, the key, the value and
// what is allowed (internal to src/spec).
#include <toml++/toml.h>

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <set>
#include <sstream>
#include <string>

#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim::spec_detail {

/// Text with its control characters written as TOML escapes them (\n, \t, \u0000, ...),
/// so that a one-line message shows them instead of breaking or ending there.
inline std::string printable(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '\n')
            out += "\\n";
        else if (c == '\t')
            out += "\\t";
        else if (c == '\r')
            out += "\\r";
        else if (u < 0x20 || u == 0x7f) {
            char code[8];
            std::snprintf(code, sizeof code, "\\u%04X", u);
            out += code;
        } else
            out.push_back(c);
    }
    return out;
}

inline std::string show(const toml::node& node) {
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
    else if (auto d = node.value<double>(); d && node.is_floating_point()) {
        // As written: the shortest text that reads back the same, with a point (32.0, not 32).
        char text[32];
        const auto end = std::to_chars(text, text + sizeof text, *d).ptr;
        std::string written(text, end);
        if (written.find_first_of(".enai") == std::string::npos) written += ".0";
        os << written;
    } else if (auto b = node.value<bool>())
        os << (*b ? "true" : "false");
    else if (auto date = node.as_date())
        os << date->get() << " (a date)";
    else if (auto time = node.as_time())
        os << time->get() << " (a time)";
    else if (auto date_time = node.as_date_time())
        os << date_time->get() << " (a date and time)";
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

/// Where a parameter is written in a campaign file, for messages: "[sweep] phi".
inline std::string location(const ParamInfo& info) {
    std::string out = "[";
    out.append(info.table).append("] ").append(info.toml_key);
    return out;
}

}  // namespace jamsim::spec_detail

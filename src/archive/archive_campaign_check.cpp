// An archive against the campaign stored in it (archive_detail.hpp, campaign_mismatch): the
// check that a hand-edited or broken copy did not keep a campaign's name over other data.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "archive_detail.hpp"
#include "jamsim/archive/archive.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/run/model_registry.hpp"

namespace jamsim::archive_detail {

namespace {

std::string number_text(double value) { return show_value(ParamValue{value}); }

bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/// The class of the attribute `name` of `f` (H5T_NO_CLASS when it has none).
H5T_class_t attribute_class(hid_t f, const std::string& name) {
    if (H5Aexists(f, name.c_str()) <= 0) return H5T_NO_CLASS;
    const h5::Handle attr(H5Aopen(f, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
    const h5::Handle type(H5Aget_type(attr.get()), H5Tclose, "type of attribute " + name);
    return H5Tget_class(type.get());
}

/// "" when the dataset `path` exists with class `want` and the shape `shape`; else what differs.
std::string dataset_mismatch(hid_t f, const std::string& path, H5T_class_t want, const std::vector<hsize_t>& shape) {
    if (!h5::exists(f, path)) return "it has no " + path + ", which its campaign has";
    const DatasetForm form = dataset_form(f, path);
    if (form.type != want)
        return path + " is not " +
               (want == H5T_FLOAT     ? "floating-point numbers"
                : want == H5T_INTEGER ? "integers"
                                      : "text") +
               " (jamsim writes it so)";
    if (form.dims != shape)
        return path + " is " + shape_text(form.dims) + " where its campaign makes it " + shape_text(shape);
    return "";
}

/// The stored campaign itself: it parses and is the campaign of the archive's fingerprint.
std::string stored_campaign(hid_t f, CampaignSpec& spec) {
    if (attribute_class(f, "spec_text") != H5T_STRING) return "it has no stored campaign (attribute spec_text)";
    try {
        spec =
            parse_stored_campaign(h5::read_string_attribute(f, "spec_text"), h5::read_string_attribute(f, "spec_path"));
    } catch (const SpecError& e) { return e.what(); }
    if (fingerprint(spec) != h5::read_string_attribute(f, "spec_fingerprint"))
        return "its stored campaign (attribute spec_text) is not the campaign of its spec_fingerprint";
    if (h5::read_int64_attribute(f, "n_replicas") != static_cast<std::int64_t>(spec.replicas.size()))
        return "n_replicas is " + std::to_string(h5::read_int64_attribute(f, "n_replicas")) +
               " where its stored campaign has " + std::to_string(spec.replicas.size()) + " replicas";
    return "";
}

/// The root's text parameters and the per-replica columns against the campaign's values.
std::string parameters_mismatch(hid_t f, const CampaignSpec& spec) {
    for (const ParamInfo* info : used_parameters(spec.replicas.front())) {
        if (is_numeric(*info)) continue;
        const std::string name(info->key), want = show_value(get_value(spec.replicas.front(), *info));
        if (attribute_class(f, name) != H5T_STRING) return "its attribute " + name + " is missing or not text";
        if (const std::string have = h5::read_string_attribute(f, name); have != want)
            return "its attribute " + name + " is \"" + have + "\" where its stored campaign says \"" + want + "\"";
    }
    const auto n = static_cast<hsize_t>(spec.replicas.size());
    for (const Column& c : parameter_columns(spec)) {
        const std::string path = "/replicas/" + c.name;
        if (std::string bad = dataset_mismatch(f, path, H5T_FLOAT, {n}); !bad.empty()) return bad;
        // Its values are the cost model's, which a later version may change (status read a
        // missing one with HDF5's "open failed").
        if (c.name == "estimated_cost") continue;
        const std::vector<double> stored = h5::read_dataset(f, path);
        for (std::size_t r = 0; r < stored.size(); ++r)
            if (const double want = c.value(spec.replicas[r]); !same_value(stored[r], want))
                return path + "[" + std::to_string(r) + "] is " + number_text(stored[r]) +
                       " where its stored campaign says " + number_text(want);
    }
    if (std::string bad = dataset_mismatch(f, "/replicas/identity", H5T_INTEGER, {n}); !bad.empty()) return bad;
    const auto identity = h5::read_all<std::uint64_t>(f, "/replicas/identity", H5T_NATIVE_UINT64);
    for (std::size_t r = 0; r < identity.size(); ++r)
        if (identity[r] != replica_identity(spec.replicas[r]))
            return "/replicas/identity[" + std::to_string(r) + "] is not the identity of its replica's parameters";
    return "";
}

/// Every dataset a run writes, of the class and shape the campaign gives it.
std::string datasets_mismatch(hid_t f, const CampaignSpec& spec) {
    const ArchiveLayout layout = archive_layout(spec);
    const auto n = static_cast<hsize_t>(spec.replicas.size());
    struct Wanted {
        std::string path;
        H5T_class_t type;
        std::vector<hsize_t> shape;
    };
    std::vector<Wanted> wanted = {{"/replicas/status", H5T_INTEGER, {n}},
                                  {"/replicas/rank", H5T_INTEGER, {n}},
                                  {"/replicas/wall_seconds", H5T_FLOAT, {n}},
                                  {"/replicas/rows_written", H5T_INTEGER, {n}},
                                  {"/replicas/progress", H5T_FLOAT, {n}},
                                  {"/replicas/force_evaluations", H5T_INTEGER, {n}},
                                  {"/replicas/failure_reason", H5T_STRING, {n}},
                                  {"/replicas/particle_offset", H5T_INTEGER, {n}},
                                  {"/final/box_side", H5T_FLOAT, {n}},
                                  {"/final/box_strain", H5T_FLOAT, {n}},
                                  {"/correlation/x", H5T_FLOAT, {n, layout.bins}},
                                  {"/correlation/g_y", H5T_FLOAT, {n, layout.bins}}};
    for (const char* name : {"x", "y", "diameter"})
        wanted.push_back({std::string("/final/") + name, H5T_FLOAT, {layout.particles}});
    for (const auto& c : kSampleColumns)
        wanted.push_back({std::string("/timeseries/") + c.name, H5T_FLOAT, {n, layout.samples}});
    if (!spec.predecessor.empty()) wanted.push_back({"/replicas/predecessor", H5T_INTEGER, {n}});
    if (layout.frames > 0) {
        for (const char* name : {"x", "y"})
            wanted.push_back({std::string("/frames/") + name, H5T_FLOAT, {layout.frames, layout.particles}});
        for (const char* name : {"strain", "box_strain"})
            wanted.push_back({std::string("/frames/") + name, H5T_FLOAT, {n, layout.frames}});
    }
    for (const Wanted& w : wanted)
        if (std::string bad = dataset_mismatch(f, w.path, w.type, w.shape); !bad.empty()) return bad;
    if (!spec.predecessor.empty() &&
        h5::read_all<std::int64_t>(f, "/replicas/predecessor", H5T_NATIVE_INT64) != spec.predecessor)
        return "/replicas/predecessor is not its stored campaign's rate ladder";
    return "";
}

}  // namespace

CampaignSpec parse_stored_campaign(const std::string& text, const std::string& spec_path) {
    try {
        return parse_campaign(text, spec_path, std::numeric_limits<std::int64_t>::max());
    } catch (const SpecError& e) {
        std::string why = e.what();
        if (why.rfind(spec_path + ":", 0) == 0) why = "line " + why.substr(spec_path.size() + 1);
        throw SpecError("its stored campaign (attribute spec_text, a copy of '" + spec_path + "') does not parse (" +
                        why + ")");
    }
}

std::string campaign_mismatch(hid_t f) {
    CampaignSpec spec;
    if (std::string bad = stored_campaign(f, spec); !bad.empty()) return bad;
    if (spec.replicas.empty()) return "";
    if (std::string bad = parameters_mismatch(f, spec); !bad.empty()) return bad;
    return datasets_mismatch(f, spec);
}

}  // namespace jamsim::archive_detail

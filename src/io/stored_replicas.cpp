#include "jamsim/io/stored_replicas.hpp"

#include <cmath>
#include <utility>

#include "jamsim/io/hdf5.hpp"

namespace jamsim {

namespace {
/// A column of /replicas, or NaN for every replica when the campaign's model reads no such
/// parameter (rate at a minimisation protocol).
std::vector<double> column_or_nan(hid_t f, const std::string& name, std::size_t replicas) {
    const htri_t exists = H5Lexists(f, ("/replicas/" + name).c_str(), H5P_DEFAULT);
    h5::check(static_cast<hid_t>(exists), "look up /replicas/" + name);
    if (exists > 0) return h5::read_dataset(f, "/replicas/" + name);
    return std::vector<double>(replicas, std::nan(""));
}
}  // namespace

const char* status_word(int status) {
    switch (status) {
    case 0: return "pending";
    case 1: return "running";
    case 2: return "done";
    case 3: return "failed";
    default: return "of unknown status";
    }
}

StoredReplicas::StoredReplicas(const std::string& archive) : path_(archive) {
    h5::quiet_errors();
    const h5::Handle f = h5::open_unlocked_readonly(archive);
    campaign_ = h5::read_string_attribute(f.get(), "campaign");
    code_version_ = h5::read_string_attribute(f.get(), "code_version");
    model_ = h5::read_string_attribute(f.get(), "model");
    status_ = h5::read_all<std::int8_t>(f.get(), "/replicas/status", H5T_NATIVE_INT8);
    const std::size_t r = status_.size();
    n_ = h5::read_dataset(f.get(), "/replicas/N");
    phi_ = h5::read_dataset(f.get(), "/replicas/phi");
    seed_ = h5::read_dataset(f.get(), "/replicas/seed");
    n_samples_ = h5::read_dataset(f.get(), "/replicas/n_samples");
    rate_ = column_or_nan(f.get(), "rate", r);
    size_ratio_ = column_or_nan(f.get(), "size_ratio", r);
    if (n_.size() != r || phi_.size() != r || seed_.size() != r || n_samples_.size() != r)
        throw h5::Error("the columns of /replicas in '" + archive + "' differ in length");
}

FinalConfiguration read_final_configuration(hid_t archive, std::int64_t id, std::int64_t n) {
    const auto k = static_cast<hsize_t>(id), disks = static_cast<hsize_t>(n);
    FinalConfiguration c;
    for (auto* v : {&c.x, &c.y, &c.diameter}) v->resize(disks);
    const bool rows = h5::dataset_shape(archive, "/final/x").size() == 2;  // layout 3
    std::int64_t first = 0;
    if (!rows) h5::read_block(archive, "/replicas/particle_offset", H5T_NATIVE_INT64, {k}, {1}, &first);
    for (const auto& [name, v] : {std::pair{"/final/x", &c.x}, {"/final/y", &c.y}, {"/final/diameter", &c.diameter}}) {
        if (rows)
            h5::read_block(archive, name, H5T_NATIVE_DOUBLE, {k, 0}, {1, disks}, v->data());
        else
            h5::read_block(archive, name, H5T_NATIVE_DOUBLE, {static_cast<hsize_t>(first)}, {disks}, v->data());
    }
    h5::read_block(archive, "/final/box_side", H5T_NATIVE_DOUBLE, {k}, {1}, &c.box_side);
    h5::read_block(archive, "/final/box_strain", H5T_NATIVE_DOUBLE, {k}, {1}, &c.box_strain);
    return c;
}

std::string damaged_final(const FinalConfiguration& c) {
    if (!(std::isfinite(c.box_side) && c.box_side > 0.0)) return "has box_side = " + show_value(c.box_side);
    // The box keeps its strain in [-1/2, 1/2) (Box::wrap_count_for); 7 was exported as a tilt of 7 box sides.
    if (!(std::abs(c.box_strain) <= 0.5))
        return "has box_strain = " + show_value(c.box_strain) + " (the box keeps it from -1/2 to 1/2)";
    for (std::size_t i = 0; i < c.x.size(); ++i) {
        if (!std::isfinite(c.x[i])) return "has x = " + show_value(c.x[i]) + " at disk " + std::to_string(i);
        if (!std::isfinite(c.y[i])) return "has y = " + show_value(c.y[i]) + " at disk " + std::to_string(i);
        if (!(std::isfinite(c.diameter[i]) && c.diameter[i] > 0.0))
            return "has diameter = " + show_value(c.diameter[i]) + " at disk " + std::to_string(i);
    }
    return "";
}

StoredReplica StoredReplicas::read(std::int64_t id) const {
    const auto k = static_cast<std::size_t>(id);
    const auto kk = static_cast<hsize_t>(id);
    StoredReplica out{.id = id,
                      .model = model_,
                      .n = n_.at(k),
                      .phi = phi_[k],
                      .rate = rate_[k],
                      .seed = seed_[k],
                      .size_ratio = size_ratio_[k],
                      .final = {}};
    const auto n = static_cast<hsize_t>(n_[k]);
    h5::quiet_errors();
    const h5::Handle f = h5::open_unlocked_readonly(path_);
    out.final = read_final_configuration(f.get(), id, static_cast<std::int64_t>(n));
    const double samples = n_samples_[k];
    if (!(samples >= 1)) throw h5::Error("replica " + std::to_string(id) + " of '" + path_ + "' has no rows");
    const auto last = static_cast<hsize_t>(samples) - 1;
    for (const auto& [name, v] : {std::pair{"energy_per_particle", &out.energy_per_particle},
                                  {"pressure", &out.pressure},
                                  {"shear_stress", &out.shear_stress},
                                  {"strain", &out.strain},
                                  {"time", &out.time}})
        h5::read_block(f.get(), std::string("/timeseries/") + name, H5T_NATIVE_DOUBLE, {kk, last}, {1, 1}, v);
    return out;
}

}  // namespace jamsim

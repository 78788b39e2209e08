#include "jamsim/io/checkpoint_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <filesystem>

#include "jamsim/core/version.hpp"
#include "jamsim/io/hdf5.hpp"

namespace jamsim {

namespace {

/// The format of the file and of what it means: v1 with fingerprint v6 (identity-keyed
/// random numbers, caches dropped at checkpoint steps).
constexpr const char* kFormat = "jamsim checkpoint 2 (campaign v7)";

void sync_file(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    const bool ok = fd >= 0 && ::fsync(fd) == 0;
    if (fd >= 0) ::close(fd);
    if (!ok) throw std::runtime_error("cannot sync '" + path + "' to disk");
}

void sync_folder(const std::string& folder) {
    const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd >= 0) {
        ::fsync(fd);  // the rename itself; best effort (not every filesystem supports it)
        ::close(fd);
    }
}

template <class T> void write_vector(hid_t g, const std::string& name, const std::vector<T>& v, hid_t type) {
    const hsize_t dims[1] = {v.size()};
    h5::Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "dataspace of " + name);
    h5::Handle set(H5Dcreate2(g, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                   H5Dclose, "create " + name);
    if (!v.empty()) h5::check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "write " + name);
    set.close(name);
}

} // namespace

std::string checkpoint_folder(const std::string& archive_path) { return archive_path + ".checkpoints"; }

std::string checkpoint_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/replica_" + std::to_string(id) + ".h5";
}

std::string end_state_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/end_" + std::to_string(id) + ".h5";
}

void write_checkpoint(const std::string& path, const ReplicaParams& p, const ReplicaState& state,
                      bool final) {
    h5::quiet_errors();
    namespace fs = std::filesystem;
    const fs::path folder = fs::path(path).parent_path();
    fs::create_directories(folder);
    const std::string tmp = path + ".tmp";
    try {
        auto file = h5::create_file(tmp);
        const hid_t f = file.get();
        h5::write_attribute(f, "format", std::string(kFormat));
        h5::write_attribute(f, "code_version", std::string(kVersion));
        h5::write_attribute(f, "replica", describe_without_run_length(p));
        h5::write_attribute(f, "final", std::int64_t{final ? 1 : 0});
        h5::write_attribute(f, "step", state.step);
        h5::write_attribute(f, "steps", state.steps);
        h5::write_attribute(f, "force_evaluations", state.force_evaluations);
        h5::write_attribute(f, "list_builds", state.list_builds);
        h5::write_attribute(f, "wall_seconds", state.wall_seconds);
        h5::write_attribute(f, "box_side", state.system.box.side());
        h5::write_attribute(f, "box_strain", state.system.box.strain());
        const Particles& q = state.system.particles;
        {
            auto g = h5::create_group(f, "particles");  // memory order: the order matters
            for (const auto& [name, v] : {std::pair{"x", &q.x}, {"y", &q.y}, {"diameter", &q.diameter},
                                          {"fx", &q.fx}, {"fy", &q.fy}, {"ux", &q.ux}, {"uy", &q.uy}})
                write_vector(g.get(), name, *v, H5T_NATIVE_DOUBLE);
            write_vector(g.get(), "tag", q.tag, H5T_NATIVE_INT32);
            g.close("particles");
        }
        {
            auto g = h5::create_group(f, "timeseries");
            for (const auto& c : kSampleColumns) write_vector(g.get(), c.name, state.series.column(c.member), H5T_NATIVE_DOUBLE);
            g.close("timeseries");
        }
        {
            auto g = h5::create_group(f, "correlation");
            write_vector(g.get(), "sum", state.correlation.sum, H5T_NATIVE_DOUBLE);
            write_vector(g.get(), "count", state.correlation.count, H5T_NATIVE_DOUBLE);
            h5::write_attribute(g.get(), "uy2_sum", state.correlation.uy2_sum);
            h5::write_attribute(g.get(), "uy2_count", state.correlation.uy2_count);
            g.close("correlation");
        }
        write_vector(f, "protocol", state.protocol, H5T_NATIVE_DOUBLE);
        h5::check(H5Fflush(f, H5F_SCOPE_GLOBAL), "flush '" + tmp + "'");
        file.close("checkpoint '" + tmp + "'");
        if (!final) sync_file(tmp);
        fs::rename(tmp, path);
        if (!final) sync_folder(folder.string());
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
}

namespace {
/// Everything in the file; checks its format and the lengths of its arrays.
ReplicaState read_state(const std::string& path) {
    h5::quiet_errors();
    try {
        const h5::Handle file = h5::open_file_readonly(path);
        const hid_t f = file.get();
        const std::string format = h5::read_string_attribute(f, "format");
        if (format != kFormat)
            throw CheckpointError("checkpoint '" + path + "' has format \"" + format +
                                  "\", this jamsim reads \"" + kFormat + "\": remove it to start the replica again");
        ReplicaState s{.system = System{Particles{}, Box(h5::read_double_attribute(f, "box_side"),
                                                         h5::read_double_attribute(f, "box_strain"))}};
        s.step = h5::read_int64_attribute(f, "step");
        s.steps = h5::read_int64_attribute(f, "steps");
        s.force_evaluations = h5::read_int64_attribute(f, "force_evaluations");
        s.list_builds = h5::read_int64_attribute(f, "list_builds");
        s.wall_seconds = h5::read_double_attribute(f, "wall_seconds");
        Particles& q = s.system.particles;
        for (const auto& [name, v] : {std::pair{"x", &q.x}, {"y", &q.y}, {"diameter", &q.diameter},
                                      {"fx", &q.fx}, {"fy", &q.fy}, {"ux", &q.ux}, {"uy", &q.uy}})
            *v = h5::read_dataset(f, std::string("particles/") + name);
        q.tag = h5::read_all<std::int32_t>(f, "particles/tag", H5T_NATIVE_INT32);
        for (const auto* v : {&q.y, &q.diameter, &q.fx, &q.fy, &q.ux, &q.uy})
            if (v->size() != q.x.size() || q.tag.size() != q.x.size())
                throw CheckpointError("checkpoint '" + path + "' is damaged: particle arrays differ in length");
        std::vector<std::vector<double>> columns;
        for (const auto& c : kSampleColumns) columns.push_back(h5::read_dataset(f, std::string("timeseries/") + c.name));
        for (std::size_t row = 0; row < columns.front().size(); ++row) {
            Sample sample{};
            for (std::size_t k = 0; k < columns.size(); ++k) sample.*(kSampleColumns[k].member) = columns[k].at(row);
            s.series.push(sample);
        }
        s.correlation.sum = h5::read_dataset(f, "correlation/sum");
        s.correlation.count = h5::read_dataset(f, "correlation/count");
        const h5::Handle g(H5Gopen2(f, "correlation", H5P_DEFAULT), H5Gclose, "open correlation");
        s.correlation.uy2_sum = h5::read_double_attribute(g.get(), "uy2_sum");
        s.correlation.uy2_count = h5::read_double_attribute(g.get(), "uy2_count");
        s.protocol = h5::read_dataset(f, "protocol");
        return s;
    } catch (const h5::Error& e) {
        throw CheckpointError("checkpoint '" + path + "' cannot be read: " + e.what());
    }
}

} // namespace

ReplicaState read_checkpoint(const std::string& path, const ReplicaParams& p) {
    h5::quiet_errors();
    std::string replica;
    try {
        replica = h5::read_string_attribute(h5::open_file_readonly(path).get(), "replica");
    } catch (const h5::Error& e) {
        throw CheckpointError("checkpoint '" + path + "' cannot be read: " + e.what());
    }
    ReplicaState s = read_state(path);
    if (replica != describe_without_run_length(p))
        throw CheckpointError("checkpoint '" + path + "' belongs to another replica (\"" + replica +
                              "\", this campaign's is \"" + describe_without_run_length(p) + "\")");
    if (!model_of(p).open_ended && s.step > checkpointed_steps(p))
        throw CheckpointError("checkpoint '" + path + "' is at step " + std::to_string(s.step) +
                              ", beyond this replica's " + std::to_string(checkpointed_steps(p)) +
                              " steps (a shorter run than the one it was saved in)");
    return s;
}

System read_state_system(const std::string& path) { return read_state(path).system; }

void check_checkpoint_header(const std::string& path, const ReplicaParams& p) {
    h5::quiet_errors();
    std::string format, replica;
    try {
        const h5::Handle f = h5::open_file_readonly(path);
        format = h5::read_string_attribute(f.get(), "format");
        replica = h5::read_string_attribute(f.get(), "replica");
    } catch (const h5::Error& e) {
        throw CheckpointError("checkpoint '" + path + "' cannot be read: " + e.what());
    }
    if (format != kFormat)
        throw CheckpointError("checkpoint '" + path + "' has format \"" + format + "\", this jamsim reads \"" +
                              kFormat + "\": remove it to start the replica again");
    if (replica != describe_without_run_length(p))
        throw CheckpointError("checkpoint '" + path + "' belongs to another replica (\"" + replica +
                              "\", this campaign's is \"" + describe_without_run_length(p) + "\")");
}

} // namespace jamsim

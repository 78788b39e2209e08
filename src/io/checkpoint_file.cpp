#include "jamsim/io/checkpoint_file.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <ctime>

#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>

#include "jamsim/core/digest.hpp"
#include "jamsim/core/version.hpp"
#include "jamsim/io/hdf5.hpp"
#include "jamsim/io/global_heap_check.hpp"
#include "jamsim/io/read_deadline.hpp"

namespace jamsim {

namespace {

/// The per-disk columns of a checkpoint's `particles` group, in the file's order (`P` is
/// Particles or const Particles).
template <class P> auto particle_columns(P& q) {
    using Column = decltype(&q.x);
    return std::array<std::pair<const char*, Column>, 7>{{{"x", &q.x},
                                                          {"y", &q.y},
                                                          {"diameter", &q.diameter},
                                                          {"fx", &q.fx},
                                                          {"fy", &q.fy},
                                                          {"ux", &q.ux},
                                                          {"uy", &q.uy}}};
}

/// The format of the file and of what it means: v1 with fingerprint v6 (identity-keyed
/// random numbers, caches dropped at checkpoint steps).
constexpr const char* kFormat = "jamsim checkpoint 2 (campaign v7)";

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
    h5::Handle set(H5Dcreate2(g, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
                   "create " + name);
    if (!v.empty()) h5::check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "write " + name);
    set.close(name);
}

/// A digest of everything a checkpoint holds (its scalars, then every array in file order),
/// stored as the attribute "checksum", so a file edited or damaged after it was written (an
/// edited step, a column a row short, zeros where data were) is recognised before it is used.
std::int64_t digest_of(const ReplicaState& state) {
    Digest d;
    d.add(state.step);
    d.add(state.steps);
    d.add(state.force_evaluations);
    d.add(state.list_builds);
    d.add(state.wall_seconds);
    d.add(state.system.box.side());
    d.add(state.system.box.strain());
    const Particles& q = state.system.particles;
    for (const auto& [name, v] : particle_columns(q)) d.add(*v);
    d.add(q.tag);
    for (const auto& c : kSampleColumns) d.add(state.series.column(c.member));
    d.add(state.correlation.sum);
    d.add(state.correlation.count);
    d.add(state.correlation.uy2_sum);
    d.add(state.correlation.uy2_count);
    d.add(state.protocol);
    return static_cast<std::int64_t>(d.value());
}

}  // namespace

std::string checkpoint_folder(const std::string& archive_path) { return archive_path + ".checkpoints"; }

std::string checkpoint_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/replica_" + std::to_string(id) + ".h5";
}

std::string progress_note_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/replica_" + std::to_string(id) + ".progress";
}

void write_progress_note(const std::string& path, double fraction) {
    const std::string tmp = path + ".tmp";
    std::FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f) {  // the first note of a run: the folder may not be there yet
        std::error_code ignored;
        std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ignored);
        f = std::fopen(tmp.c_str(), "w");
    }
    if (!f) return;
    const double now = static_cast<double>(std::time(nullptr));
    const bool written = std::fprintf(f, "%.6f %.0f\n", fraction, now) > 0;
    if (std::fclose(f) == 0 && written) std::rename(tmp.c_str(), path.c_str());
}

std::optional<ProgressNote> read_progress_note(const std::string& path) {
    // O_NONBLOCK and a regular file only: a FIFO of that name blocked `jamsim status` for good.
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) return std::nullopt;
    struct stat st {};
    std::FILE* f = ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) ? ::fdopen(fd, "r") : nullptr;
    if (!f) {
        ::close(fd);
        return std::nullopt;
    }
    double fraction = 0, when = 0;
    const int read = std::fscanf(f, "%lf %lf", &fraction, &when);
    std::fclose(f);
    if (read != 2 || !(fraction >= 0 && fraction <= 1)) return std::nullopt;
    return ProgressNote{fraction, std::max(0.0, static_cast<double>(std::time(nullptr)) - when)};
}

std::string end_state_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/end_" + std::to_string(id) + ".h5";
}

std::string rebuild_state_path(const std::string& archive_path, std::int64_t id) {
    return checkpoint_folder(archive_path) + "/rebuild_" + std::to_string(id) + ".h5";
}

void write_checkpoint(const std::string& path, const ReplicaParams& p, const ReplicaState& state, bool final) {
    h5::quiet_errors();
    namespace fs = std::filesystem;
    const fs::path folder = fs::path(path).parent_path();
    fs::create_directories(folder);
    const std::string tmp = path + ".tmp";
    try {
        h5::FileInMemory file(tmp);
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
            for (const auto& [name, v] : particle_columns(q)) write_vector(g.get(), name, *v, H5T_NATIVE_DOUBLE);
            write_vector(g.get(), "tag", q.tag, H5T_NATIVE_INT32);
            g.close("particles");
        }
        {
            auto g = h5::create_group(f, "timeseries");
            for (const auto& c : kSampleColumns)
                write_vector(g.get(), c.name, state.series.column(c.member), H5T_NATIVE_DOUBLE);
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
        h5::write_attribute(f, "checksum", digest_of(state));
        file.write_and_close(/*sync=*/!final);  // a final one costs only recomputation if lost
        fs::rename(tmp, path);
        if (!final) sync_folder(folder.string());
    } catch (...) {
        std::error_code ignored;
        fs::remove(tmp, ignored);
        throw;
    }
}

namespace {
bool all_finite(const std::vector<double>& v) {
    for (const double x : v)
        if (!std::isfinite(x)) return false;
    return true;
}

/// Why the state read from a checkpoint cannot be a state of a replica of `n` disks ("" when
/// it can): array lengths, finite values, a step within the run, tags that are disk indices.
std::string body_problem(const ReplicaState& s, std::int64_t n) {
    const Particles& q = s.system.particles;
    const auto size = static_cast<std::size_t>(n);
    for (const auto& [name, v] : particle_columns(q)) {
        if (v->size() != size)
            return std::string("particles/") + name + " holds " + std::to_string(v->size()) +
                   " values, the replica has N = " + std::to_string(n);
        if (!all_finite(*v)) return std::string("particles/") + name + " holds a value that is not finite";
    }
    if (q.tag.size() != size)
        return "particles/tag holds " + std::to_string(q.tag.size()) +
               " values, the replica has N = " + std::to_string(n);
    for (const std::int32_t t : q.tag)
        if (t < 0 || t >= n)
            return "particles/tag holds " + std::to_string(t) + ", not a disk index below N = " + std::to_string(n);
    for (const double d : q.diameter)
        if (!(d > 0)) return "particles/diameter holds a diameter that is not positive";
    const double side = s.system.box.side(), strain = s.system.box.strain();
    if (!(side > 0) || !std::isfinite(side) || !std::isfinite(strain))
        return "the box (side, strain) is not finite and positive";
    if (s.step < 0 || s.steps < 0 || s.step > s.steps)
        return "step " + std::to_string(s.step) + " is not within the run's " + std::to_string(s.steps) + " steps";
    return "";
}

/// What the read deadline advises for a checkpoint on which HDF5 loops.
constexpr const char* kDamagedCheckpointAdvice = "remove it: its replica starts again from its start";

/// A checkpoint whose global heap HDF5 would loop on (blocks a crash zeroed): damaged, as an
/// unreadable one (the read deadline is the backstop for other such loops). Each public reader
/// calls it once, before any HDF5 read.
void check_global_heaps(const std::string& path) {
    if (const std::string why = damaged_global_heap(path); !why.empty())
        throw CheckpointUnreadable("checkpoint '" + path + "' is damaged: " + why);
}

/// Everything in the file; checks its format, the lengths of its arrays and its checksum (which
/// every file of this format has); with `n` >= 0 also the body against a replica of n disks.
ReplicaState read_state(const std::string& path, std::int64_t n = -1) {
    h5::quiet_errors();
    ReplicaState s{.system = System{Particles{}, Box(1.0)}};  // the box is read below
    std::optional<std::int64_t> checksum;
    try {
        const ReadDeadline deadline(path, read_deadline_seconds(), kDamagedCheckpointAdvice);
        const h5::Handle file = h5::open_file_readonly(path);
        const hid_t f = file.get();
        const std::string format = h5::read_string_attribute(f, "format");
        if (format != kFormat)
            throw CheckpointError("checkpoint '" + path + "' has format \"" + format + "\", this jamsim reads \"" +
                                  kFormat + "\": remove it to start the replica again");
        s.system = System{Particles{},
                          Box(h5::read_double_attribute(f, "box_side"), h5::read_double_attribute(f, "box_strain"))};
        s.step = h5::read_int64_attribute(f, "step");
        s.steps = h5::read_int64_attribute(f, "steps");
        s.force_evaluations = h5::read_int64_attribute(f, "force_evaluations");
        s.list_builds = h5::read_int64_attribute(f, "list_builds");
        s.wall_seconds = h5::read_double_attribute(f, "wall_seconds");
        // Every file of this format has one: without it an edit or damage would pass unseen.
        if (H5Aexists(f, "checksum") <= 0)
            throw CheckpointError("checkpoint '" + path + "' is damaged: its checksum is missing");
        checksum = h5::read_int64_attribute(f, "checksum");
        Particles& q = s.system.particles;
        for (const auto& [name, v] : particle_columns(q)) *v = h5::read_dataset(f, std::string("particles/") + name);
        q.tag = h5::read_all<std::int32_t>(f, "particles/tag", H5T_NATIVE_INT32);
        for (const auto* v : {&q.y, &q.diameter, &q.fx, &q.fy, &q.ux, &q.uy})
            if (v->size() != q.x.size() || q.tag.size() != q.x.size())
                throw CheckpointError("checkpoint '" + path + "' is damaged: particle arrays differ in length");
        std::vector<std::vector<double>> columns;
        for (const auto& c : kSampleColumns)
            columns.push_back(h5::read_dataset(f, std::string("timeseries/") + c.name));
        for (const auto& c : columns)
            if (c.size() != columns.front().size())
                throw CheckpointError("checkpoint '" + path + "' is damaged: its timeseries columns differ in length");
        for (std::size_t row = 0; row < columns.front().size(); ++row) {
            Sample sample{};
            for (std::size_t k = 0; k < columns.size(); ++k) sample.*(kSampleColumns[k].member) = columns[k][row];
            s.series.push(sample);
        }
        s.correlation.sum = h5::read_dataset(f, "correlation/sum");
        s.correlation.count = h5::read_dataset(f, "correlation/count");
        const h5::Handle g(H5Gopen2(f, "correlation", H5P_DEFAULT), H5Gclose, "open correlation");
        s.correlation.uy2_sum = h5::read_double_attribute(g.get(), "uy2_sum");
        s.correlation.uy2_count = h5::read_double_attribute(g.get(), "uy2_count");
        s.protocol = h5::read_dataset(f, "protocol");
    } catch (const h5::Error& e) {
        throw CheckpointError("checkpoint '" + path + "' cannot be read: " + e.what());
    } catch (const std::invalid_argument& e) {  // a box that cannot be (Box's own check)
        throw CheckpointError("checkpoint '" + path + "' is damaged: " + e.what());
    }
    if (checksum && *checksum != digest_of(s))
        throw CheckpointError("checkpoint '" + path + "' is damaged: its checksum does not match what it holds");
    if (n >= 0)
        if (const std::string why = body_problem(s, n); !why.empty())
            throw CheckpointError("checkpoint '" + path + "' is damaged: " + why);
    return s;
}

}  // namespace

ReplicaState read_checkpoint(const std::string& path, const ReplicaParams& p) {
    h5::quiet_errors();
    check_global_heaps(path);
    std::string replica;
    try {
        const ReadDeadline deadline(path, read_deadline_seconds(), kDamagedCheckpointAdvice);
        replica = h5::read_string_attribute(h5::open_file_readonly(path).get(), "replica");
    } catch (const h5::Error& e) { throw CheckpointError("checkpoint '" + path + "' cannot be read: " + e.what()); }
    ReplicaState s = read_state(path, p.n);
    if (replica != describe_without_run_length(p))
        throw CheckpointError("checkpoint '" + path + "' belongs to another replica (\"" + replica +
                              "\", this campaign's is \"" + describe_without_run_length(p) + "\")");
    if (s.series.size() > static_cast<std::size_t>(std::max<std::int64_t>(sample_count(p), 0)))
        throw CheckpointError("checkpoint '" + path + "' is damaged: it holds " + std::to_string(s.series.size()) +
                              " rows, this replica samples " + std::to_string(sample_count(p)));
    if (!model_of(p).open_ended && s.step > checkpointed_steps(p))
        throw CheckpointError("checkpoint '" + path + "' is at step " + std::to_string(s.step) +
                              ", beyond this replica's " + std::to_string(checkpointed_steps(p)) +
                              " steps (a shorter run than the one it was saved in)");
    return s;
}

System read_state_system(const std::string& path) {
    check_global_heaps(path);
    return read_state(path).system;
}

System read_state_system(const std::string& path, const ReplicaParams& p) {
    check_global_heaps(path);
    return read_state(path, p.n).system;
}

void check_checkpoint_header(const std::string& path, const ReplicaParams& p) {
    h5::quiet_errors();
    check_global_heaps(path);
    std::string format, replica;
    try {
        const ReadDeadline deadline(path, read_deadline_seconds(), kDamagedCheckpointAdvice);
        const h5::Handle f = h5::open_file_readonly(path);
        format = h5::read_string_attribute(f.get(), "format");
        replica = h5::read_string_attribute(f.get(), "replica");
    } catch (const h5::Error& e) {
        throw CheckpointUnreadable("checkpoint '" + path + "' cannot be read: " + e.what());
    }
    if (format != kFormat)
        throw CheckpointError("checkpoint '" + path + "' has format \"" + format + "\", this jamsim reads \"" +
                              kFormat + "\": remove it to start the replica again");
    if (replica != describe_without_run_length(p))
        throw CheckpointError("checkpoint '" + path + "' belongs to another replica (\"" + replica +
                              "\", this campaign's is \"" + describe_without_run_length(p) + "\")");
}

}  // namespace jamsim

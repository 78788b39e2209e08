#include "jamsim/io/hdf5.hpp"

#include "jamsim/parallel/mpi.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <optional>
#include <vector>

namespace jamsim::h5 {

void quiet_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

namespace {

/// The part of an HDF5 error description that says why: the system's errno and message of
/// the sec2 driver's long "file write failed: time = ..., errno = 28, error message = '...'",
/// the MPI error string of the MPI-IO driver's "... failed: MPI error string is '...'".
std::string why_in(std::string text) {
    if (const auto at = text.find("errno = "); at != std::string::npos) {
        const auto end = text.find(", error message = '", at);
        const auto close = end == std::string::npos ? end : text.find('\'', end + 19);
        if (close != std::string::npos)
            return "errno " + text.substr(at + 8, end - at - 8) + ", " + text.substr(end + 19, close - end - 19);
    }
    if (const auto at = text.find(": MPI error string is '"); at != std::string::npos) {
        const auto close = text.find('\'', at + 23);
        return text.substr(0, at) + ": " + text.substr(at + 23, close - at - 23);
    }
    return text;
}

}  // namespace

std::string error_cause() {
    std::string cause;
    const auto innermost = [](unsigned, const H5E_error2_t* e, void* out) -> herr_t {
        if (e->desc == nullptr || *e->desc == '\0') return 0;
        *static_cast<std::string*>(out) = e->desc;
        return 1;  // stop: the innermost description is the cause
    };
    if (H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, &cause) < 0) return "";
    return cause.empty() ? "" : why_in(cause);
}

namespace {

[[noreturn]] void end_before_hdf5_closes() {
    std::fflush(nullptr);
    std::_Exit(1);
}

}  // namespace

void file_close_failed() noexcept {
    static bool guarded = false;  // process-wide: one guard for the library's one exit
    if (guarded) return;
    guarded = true;
    int initialised = 0, finalised = 0;
    MPI_Initialized(&initialised);
    MPI_Finalized(&finalised);
    if (initialised && !finalised) {
        int key = MPI_KEYVAL_INVALID;
        const auto on_delete = [](MPI_Comm, int, void*, void*) -> int { end_before_hdf5_closes(); };
        if (MPI_Comm_create_keyval(MPI_COMM_NULL_COPY_FN, on_delete, &key, nullptr) == MPI_SUCCESS &&
            MPI_Comm_set_attr(MPI_COMM_SELF, key, nullptr) == MPI_SUCCESS)
            return;
    }
    std::atexit([] { end_before_hdf5_closes(); });
}

void fail(const std::string& what) {
    const std::string cause = error_cause();
    throw Error("HDF5: " + what + " failed" + (cause.empty() ? "" : " (" + cause + ")"));
}

FileInMemory::FileInMemory(std::string path) : path_(std::move(path)) {
    // Semi close degree: H5Fclose fails (instead of silently deferring) if any object in
    // the file is still open, so a successful close means the file is complete.
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
    check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_SEMI), "set close degree");
    constexpr std::size_t kGrowBytes = std::size_t{1} << 20;  // the image grows in 1 MiB steps
    check(H5Pset_fapl_core(fapl.get(), kGrowBytes, /*backing_store=*/0), "set the in-memory driver");
    file_ = Handle(H5Fcreate(path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                   "create file '" + path_ + "' in memory");
}

void FileInMemory::write_and_close(bool sync) {
    // The image is the file as it would be on disk after a flush (in memory: nothing can fail
    // for want of space).
    check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), "flush '" + path_ + "' in memory");
    const ssize_t size = H5Fget_file_image(file_.get(), nullptr, 0);
    check(size < 0 ? -1 : 0, "size the image of '" + path_ + "'");
    std::vector<char> image(static_cast<std::size_t>(size));
    check(H5Fget_file_image(file_.get(), image.data(), image.size()) == size ? 0 : -1,
          "copy the image of '" + path_ + "'");
    file_.close("file '" + path_ + "'");
    // A failure removes what was written and names the system's reason ("No space left on device").
    const auto fail = [&](int fd, int err) {
        if (fd >= 0) {
            ::close(fd);
            ::unlink(path_.c_str());
        }
        throw Error("writing '" + path_ + "' failed: " + std::strerror(err));
    };
    const int fd = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) fail(-1, errno);
    for (std::size_t done = 0; done < image.size();) {
        const ssize_t n = ::write(fd, image.data() + done, image.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) fail(fd, n < 0 ? errno : ENOSPC);
        done += static_cast<std::size_t>(n);
    }
    if (sync && ::fsync(fd) != 0) fail(fd, errno);
    if (::close(fd) != 0) {
        const int err = errno;
        ::unlink(path_.c_str());
        fail(-1, err);
    }
}

Handle open_file_readonly(const std::string& path) {
    return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, "open file '" + path + "'");
}

Handle create_group(hid_t parent, const std::string& name) {
    return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose,
                  "create group '" + name + "'");
}

namespace {
void write_scalar_attribute(hid_t obj, const std::string& name, hid_t type, const void* value) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "scalar dataspace");
    Handle attr(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                "create attribute '" + name + "'");
    check(H5Awrite(attr.get(), type, value), "write attribute '" + name + "'");
    attr.close("attribute '" + name + "'");
}
}  // namespace

void write_attribute(hid_t obj, const std::string& name, double value) {
    write_scalar_attribute(obj, name, H5T_NATIVE_DOUBLE, &value);
}

void write_attribute(hid_t obj, const std::string& name, std::int64_t value) {
    write_scalar_attribute(obj, name, H5T_NATIVE_INT64, &value);
}

void write_attribute(hid_t obj, const std::string& name, const std::string& value) {
    // Variable-length UTF-8, so that h5py reads it back as str.
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    check(H5Tset_size(type.get(), H5T_VARIABLE), "string size");
    check(H5Tset_cset(type.get(), H5T_CSET_UTF8), "string charset");
    const char* text = value.c_str();
    write_scalar_attribute(obj, name, type.get(), &text);
}

void write_dataset(hid_t parent, const std::string& name, std::span<const double> values, const std::string& units,
                   const std::string& description) {
    const hsize_t dims[1] = {values.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "dataspace for '" + name + "'");
    Handle set(H5Dcreate2(parent, name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose, "create dataset '" + name + "'");
    if (!values.empty())
        check(H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              "write dataset '" + name + "'");
    write_attribute(set.get(), "units", units);
    write_attribute(set.get(), "description", description);
    set.close("dataset '" + name + "'");
}

std::vector<double> read_dataset(hid_t parent, const std::string& name) {
    Handle set(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose, "open dataset '" + name + "'");
    Handle space(H5Dget_space(set.get()), H5Sclose, "dataspace of '" + name + "'");
    const hssize_t count = H5Sget_simple_extent_npoints(space.get());
    check(static_cast<hid_t>(count), "size of '" + name + "'");
    std::vector<double> out(static_cast<std::size_t>(count));
    if (count > 0)
        check(H5Dread(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()),
              "read dataset '" + name + "'");
    return out;
}

double read_double_attribute(hid_t obj, const std::string& name) {
    Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute '" + name + "'");
    double v = 0.0;
    check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), "read attribute '" + name + "'");
    return v;
}

std::int64_t read_int64_attribute(hid_t obj, const std::string& name) {
    Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute '" + name + "'");
    std::int64_t v = 0;
    check(H5Aread(attr.get(), H5T_NATIVE_INT64, &v), "read attribute '" + name + "'");
    return v;
}

std::string read_string_attribute(hid_t obj, const std::string& name) {
    const htri_t exists = H5Aexists(obj, name.c_str());
    check(exists, "look up attribute " + name);
    if (exists == 0) return "";
    Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
    Handle type(H5Aget_type(attr.get()), H5Tclose, "type of " + name);
    if (H5Tis_variable_str(type.get()) > 0) {
        char* text = nullptr;
        check(H5Aread(attr.get(), type.get(), &text), "read attribute " + name);
        std::string out = text ? text : "";
        H5free_memory(text);
        return out;
    }
    std::string out(H5Tget_size(type.get()), '\0');
    check(H5Aread(attr.get(), type.get(), out.data()), "read attribute " + name);
    return out.substr(0, out.find('\0'));
}

void replace_attribute(hid_t obj, const std::string& name, const std::string& value) {
    if (H5Aexists(obj, name.c_str()) > 0) check(H5Adelete(obj, name.c_str()), "replace attribute " + name);
    write_attribute(obj, name, value);
}

void replace_attribute(hid_t obj, const std::string& name, std::int64_t value) {
    if (H5Aexists(obj, name.c_str()) > 0) check(H5Adelete(obj, name.c_str()), "replace attribute " + name);
    write_attribute(obj, name, value);
}

void create_fixed_text_attribute(hid_t obj, const std::string& name, std::size_t capacity) {
    Handle type(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    check(H5Tset_size(type.get(), capacity), "string size");
    check(H5Tset_strpad(type.get(), H5T_STR_NULLPAD), "string padding");
    const std::string empty(capacity, '\0');
    write_scalar_attribute(obj, name, type.get(), empty.data());
}

namespace {
/// The attribute `name` of `obj` when it exists and `fits` its type and number of values.
std::optional<Handle> attribute_that_fits(hid_t obj, const std::string& name,
                                          const std::function<bool(hid_t type)>& fits) {
    const htri_t exists = H5Aexists(obj, name.c_str());
    check(exists, "look up attribute " + name);
    if (exists == 0) return std::nullopt;
    Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose, "open attribute " + name);
    const Handle type(H5Aget_type(attr.get()), H5Tclose, "type of attribute " + name);
    const Handle space(H5Aget_space(attr.get()), H5Sclose, "space of attribute " + name);
    if (H5Sget_simple_extent_npoints(space.get()) != 1 || !fits(type.get())) return std::nullopt;
    return attr;
}
}  // namespace

void overwrite_attribute(hid_t obj, const std::string& name, const std::string& value) {
    std::size_t room = 0;
    const auto attr = attribute_that_fits(obj, name, [&](hid_t type) {
        room = H5Tget_size(type);
        return H5Tget_class(type) == H5T_STRING && H5Tis_variable_str(type) == 0 && room >= value.size();
    });
    if (!attr) return replace_attribute(obj, name, value);
    Handle type(H5Aget_type(attr->get()), H5Tclose, "type of attribute " + name);
    std::string padded = value;
    padded.resize(room, '\0');
    check(H5Awrite(attr->get(), type.get(), padded.data()), "write attribute " + name);
}

void overwrite_attribute(hid_t obj, const std::string& name, std::int64_t value) {
    const auto attr = attribute_that_fits(
        obj, name, [](hid_t type) { return H5Tget_class(type) == H5T_INTEGER && H5Tget_size(type) == 8; });
    if (!attr) return replace_attribute(obj, name, value);
    check(H5Awrite(attr->get(), H5T_NATIVE_INT64, &value), "write attribute " + name);
}

Handle mpio_file_access(MPI_Comm comm) {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
    check(H5Pset_fapl_mpio(fapl.get(), comm, MPI_INFO_NULL), "MPI-IO driver");
    check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_SEMI), "close degree");
    return fapl;
}

namespace {
/// errno of a POSIX open of `path` with `flags` (the descriptor closed again), 0 on success.
int open_errno(const std::string& path, int flags) {
    const int fd = ::open(path.c_str(), flags | O_CLOEXEC, 0666);
    if (fd < 0) return errno;
    ::close(fd);
    return 0;
}

/// Collective: throws the same OpenRefused on every rank when any rank's `code` (an errno) is not 0.
void agree_on_open(MPI_Comm comm, int code, const std::string& path, const char* doing) {
    struct {
        int code, rank;
    } mine{code, mpi::rank(comm)}, worst{};
    mpi::check(MPI_Allreduce(&mine, &worst, 1, MPI_2INT, MPI_MAXLOC, comm), "MPI_Allreduce");
    if (worst.code == 0) return;
    const int ranks = mpi::size(comm);
    throw OpenRefused(std::string(doing) + " '" + path + "' failed" +
                      (ranks > 1 ? " on rank " + std::to_string(worst.rank) : std::string()) + ": " +
                      std::strerror(worst.code));
}
}  // namespace

Handle open_parallel(MPI_Comm comm, const std::string& path) {
    agree_on_open(comm, open_errno(path, O_RDWR), path, "opening");
    const auto fapl = mpio_file_access(comm);
    return Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get()), H5Fclose, "open archive '" + path + "'");
}

Handle create_parallel(MPI_Comm comm, const std::string& path) {
    const int rank = mpi::rank(comm);
    // Rank 0 makes the file, then every other rank opens it.
    bool made = false;
    int code = 0;
    if (rank == 0) {
        code = open_errno(path, O_RDWR | O_CREAT | O_EXCL);
        made = code == 0;
        if (code == EEXIST) code = open_errno(path, O_RDWR);
    }
    try {
        agree_on_open(comm, code, path, "creating");
        agree_on_open(comm, rank == 0 ? 0 : open_errno(path, O_RDWR), path, "creating");
    } catch (const OpenRefused&) {
        if (made) ::unlink(path.c_str());
        throw;
    }
    const auto fapl = mpio_file_access(comm);
    return Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                  "create archive '" + path + "'");
}

Handle open_unlocked_readonly(const std::string& path) {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
    check(H5Pset_file_locking(fapl.get(), false, true), "disable file locking");
    return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose, "open '" + path + "'");
}

Handle independent_transfer() {
    Handle dxpl(H5Pcreate(H5P_DATASET_XFER), H5Pclose, "transfer properties");
    check(H5Pset_dxpl_mpio(dxpl.get(), H5FD_MPIO_INDEPENDENT), "independent transfer");
    return dxpl;
}

Handle fixed_string_type(std::size_t bytes) {
    Handle t(H5Tcopy(H5T_C_S1), H5Tclose, "string type");
    check(H5Tset_size(t.get(), bytes), "string size");
    check(H5Tset_strpad(t.get(), H5T_STR_NULLTERM), "string padding");
    return t;
}

namespace {
void create_dataset(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t> dims, const void* fill,
                    const std::string& units, const std::string& description) {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                 "dataspace of " + path);
    Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, "creation properties");
    check(H5Pset_alloc_time(dcpl.get(), H5D_ALLOC_TIME_EARLY), "early allocation");
    check(H5Pset_fill_time(dcpl.get(), fill ? H5D_FILL_TIME_ALLOC : H5D_FILL_TIME_NEVER), "fill time");
    if (fill) check(H5Pset_fill_value(dcpl.get(), type, fill), "fill value");
    Handle set(H5Dcreate2(file, path.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), H5Dclose,
               "create dataset " + path);
    write_attribute(set.get(), "units", units);
    write_attribute(set.get(), "description", description);
    set.close(path);
}
}  // namespace

void create_filled_dataset(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t> dims, const void* fill,
                           const std::string& units, const std::string& description) {
    create_dataset(file, path, type, std::move(dims), fill, units, description);
}

void create_unfilled_dataset(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t> dims,
                             const std::string& units, const std::string& description) {
    create_dataset(file, path, type, std::move(dims), nullptr, units, description);
}

namespace {
/// The dataset, its file space with the block selected, and the block's memory space.
struct Selection {
    Handle set, space, mem;
};
Selection select_block(hid_t file, const std::string& path, const std::vector<hsize_t>& start,
                       const std::vector<hsize_t>& count) {
    Selection s;
    s.set = Handle(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "open " + path);
    s.space = Handle(H5Dget_space(s.set.get()), H5Sclose, "dataspace of " + path);
    check(H5Sselect_hyperslab(s.space.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(), nullptr),
          "select in " + path);
    s.mem = Handle(H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), H5Sclose, "memory space");
    return s;
}
}  // namespace

void write_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                 std::vector<hsize_t> count, const void* data, hid_t dxpl) {
    Selection s = select_block(file, path, start, count);
    check(H5Dwrite(s.set.get(), memtype, s.mem.get(), s.space.get(), dxpl, data), "write " + path);
    s.set.close(path);
}

void read_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                std::vector<hsize_t> count, void* data, hid_t dxpl) {
    Selection s = select_block(file, path, start, count);
    check(H5Dread(s.set.get(), memtype, s.mem.get(), s.space.get(), dxpl, data), "read " + path);
}

std::vector<hsize_t> dataset_shape(hid_t file, const std::string& path) {
    Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "open " + path);
    Handle space(H5Dget_space(set.get()), H5Sclose, "dataspace of " + path);
    const int rank = H5Sget_simple_extent_ndims(space.get());
    check(rank, "rank of " + path);
    std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
    check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr), "shape of " + path);
    return dims;
}

bool exists(hid_t file, const std::string& path) {
    // Each link of an absolute path in turn (H5Lexists fails on a missing intermediate group).
    for (std::size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1)) {
        const std::string prefix = path.substr(0, slash);
        const htri_t found = H5Lexists(file, prefix.c_str(), H5P_DEFAULT);
        check(static_cast<herr_t>(found < 0 ? -1 : 0), "look up " + prefix);
        if (found == 0) return false;
        if (slash == std::string::npos) return true;
    }
}

}  // namespace jamsim::h5

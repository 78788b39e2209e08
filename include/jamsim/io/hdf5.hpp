#pragma once
#include <hdf5.h>
#include <mpi.h>

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace jamsim::h5 {

/// Thrown for every failed HDF5 call; carries what was being done.
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Thrown alike on every rank by open_parallel and create_parallel when some rank cannot
/// open the file: nothing was opened, so the ranks can refuse together.
struct OpenRefused : Error {
    using Error::Error;
};

/// The cause HDF5's error stack gives for the call that just failed, in words: the innermost
/// entry, where a driver or the system said why ("MPI_File_write_at_all: MPI_ERR_NO_SPACE ...",
/// "errno 28, No space left on device"); "" when the stack holds none.
std::string error_cause();

/// Throws Error "HDF5: WHAT failed" with the cause from HDF5's error stack, when there is one.
[[noreturn]] void fail(const std::string& what);

/// Check an HDF5 return value (negative = failure).
inline hid_t check(hid_t id, const std::string& what) {
    if (id < 0) fail(what);
    return id;
}

/// Called when H5Fclose failed (a write the filesystem refused while HDF5 flushed the file).
/// HDF5 1.10 keeps such a file half closed, and its own close of it when the library ends
/// (at MPI_Finalize, or at exit) dereferences freed state: the process crashed with a
/// segfault after its error message (exit 139). So from the first such failure on, the
/// process ends just before that close, with exit status 1, its output flushed: through an
/// attribute on MPI_COMM_SELF set after HDF5's own (MPI_Finalize deletes them last set, first
/// called), or an exit handler registered after HDF5's where MPI is not running. A command
/// that fails so has already said why; whatever it wrote is made whole or removed by its own
/// rules before this point. The status is 1 whatever the command meant to return: `jamsim
/// run` refuses an archive whose creation failed with 2, but a refused write ends it with 1.
void file_close_failed() noexcept;

/// Move-only owner of an hid_t, closed with the matching H5*close on destruction.
class Handle {
  public:
    using Closer = herr_t (*)(hid_t);
    Handle() = default;
    Handle(hid_t id, Closer closer, const std::string& what) : id_(check(id, what)), close_(closer) {}
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, H5I_INVALID_HID)), close_(o.close_) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, H5I_INVALID_HID);
            close_ = o.close_;
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() { reset(); }

    hid_t get() const { return id_; }
    /// Close now, reporting failure (destructors cannot).
    void close(const std::string& what) {
        if (id_ >= 0) {
            const herr_t rc = close_(std::exchange(id_, H5I_INVALID_HID));
            if (rc < 0 && close_ == &H5Fclose) file_close_failed();
            check(rc, "close " + what);
        }
    }

    /// Forget the id without closing it: for a collective handle (an archive opened through
    /// MPI-IO) while an error unwinds on one rank, where a close would wait for ranks that
    /// never call it; the process is about to abort.
    void abandon() noexcept { id_ = H5I_INVALID_HID; }

  private:
    void reset() noexcept {
        if (id_ >= 0 && close_(std::exchange(id_, H5I_INVALID_HID)) < 0 && close_ == &H5Fclose) file_close_failed();
    }
    hid_t id_ = H5I_INVALID_HID;
    Closer close_ = nullptr;
};

/// Silence HDF5's automatic error stack printing: jamsim reports errors itself.
void quiet_errors();

/// A new serial HDF5 file built in memory (the core driver, no backing store) and written to
/// `path` in one piece by `write_and_close`. HDF5 never touches the disk, so a full disk or a
/// failing device surfaces as the write's errno ("No space left on device"), not as a failed
/// flush inside HDF5, which leaves its file open and crashes the library's exit handler.
class FileInMemory {
  public:
    explicit FileInMemory(std::string path);
    hid_t get() const { return file_.get(); }
    /// Close the file and write its bytes to `path` (created or truncated), with fsync when
    /// `sync` (before a rename makes it the file of record). Throws Error naming the path and
    /// the system's reason; a partial file is removed.
    void write_and_close(bool sync = false);

  private:
    std::string path_;
    Handle file_;
};
/// Existing file, read-only, serial driver.
Handle open_file_readonly(const std::string& path);
Handle create_group(hid_t parent, const std::string& name);

void write_attribute(hid_t obj, const std::string& name, double value);
void write_attribute(hid_t obj, const std::string& name, std::int64_t value);
void write_attribute(hid_t obj, const std::string& name, const std::string& value);

/// 1-D dataset of doubles with "units" and "description" attributes.
void write_dataset(hid_t parent, const std::string& name, std::span<const double> values, const std::string& units,
                   const std::string& description);

std::vector<double> read_dataset(hid_t parent, const std::string& name);
double read_double_attribute(hid_t obj, const std::string& name);
std::int64_t read_int64_attribute(hid_t obj, const std::string& name);
/// A string attribute (variable or fixed length); "" when it does not exist.
std::string read_string_attribute(hid_t obj, const std::string& name);
/// Delete the attribute if it exists, then write it.
void replace_attribute(hid_t obj, const std::string& name, const std::string& value);
void replace_attribute(hid_t obj, const std::string& name, std::int64_t value);
/// An empty text attribute of `capacity` bytes, fixed-length (NUL-padded; h5py reads it as
/// bytes). `overwrite_attribute` rewrites it where it stands: a variable-length one takes new
/// room in the file at each write, and a write of that room failing on one rank of a parallel
/// file left the file shorter than its superblock says, refused by HDF5 for good.
void create_fixed_text_attribute(hid_t obj, const std::string& name, std::size_t capacity);
/// Writes `value` over the attribute `name` where it stands when its room fits (fixed-length
/// text of at least value.size() bytes; one 64-bit integer), allocating nothing in the file;
/// else replaces it (attributes of archives made before they were fixed-length).
void overwrite_attribute(hid_t obj, const std::string& name, const std::string& value);
void overwrite_attribute(hid_t obj, const std::string& name, std::int64_t value);

// --- Parallel files (MPI-IO driver) and datasets written block by block ---

/// File access through the MPI-IO driver on `comm`, semi close degree (a close that
/// succeeds means nothing was left open).
Handle mpio_file_access(MPI_Comm comm);
/// Collective: `path` opened read-write (`open_parallel`) or created, truncated
/// (`create_parallel`), through the MPI-IO driver on every rank of `comm`. Every rank first
/// opens the file itself and the ranks agree on the outcome, so that a file one rank cannot
/// open (permissions, no descriptors left, a mount another node lacks) throws the same
/// OpenRefused on every rank: Open MPI's MPI_File_open waits forever when it fails on some ranks only
/// (the others wait in its shared-file-pointer barrier). A refused create leaves no file.
Handle open_parallel(MPI_Comm comm, const std::string& path);
Handle create_parallel(MPI_Comm comm, const std::string& path);
/// Serial read-only open that works while another job writes the file (no file locking).
Handle open_unlocked_readonly(const std::string& path);
/// Transfer properties for independent MPI-IO writes and reads.
Handle independent_transfer();
/// Fixed-length, NUL-terminated string type of `bytes` bytes.
Handle fixed_string_type(std::size_t bytes);

/// Collective: a dataset of shape `dims`, allocated now but never filled (the file stays
/// sparse until data is written: creating terabytes costs nothing; what was never written
/// reads as zeros), with "units" and "description" attributes.
void create_unfilled_dataset(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t> dims,
                             const std::string& units, const std::string& description);

/// Collective: a dataset of shape `dims`, allocated now and filled with `fill`, with "units"
/// and "description" attributes.
void create_filled_dataset(hid_t file, const std::string& path, hid_t type, std::vector<hsize_t> dims, const void* fill,
                           const std::string& units, const std::string& description);
/// Write the block [start, start + count) of a dataset with transfer properties `dxpl`
/// (independent_transfer() under MPI-IO; asking a file for its driver would be collective).
void write_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                 std::vector<hsize_t> count, const void* data, hid_t dxpl = H5P_DEFAULT);
/// Read the block [start, start + count) of a dataset into `data`.
void read_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                std::vector<hsize_t> count, void* data, hid_t dxpl = H5P_DEFAULT);
/// Shape of a dataset.
std::vector<hsize_t> dataset_shape(hid_t file, const std::string& path);
/// Whether the absolute path (e.g. "/frames/strain") names an object in the file.
bool exists(hid_t file, const std::string& path);

/// A whole dataset as a vector of T (memtype the native type of T).
template <class T>
std::vector<T> read_all(hid_t file, const std::string& path, hid_t memtype, hid_t dxpl = H5P_DEFAULT) {
    Handle set(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose, "open " + path);
    Handle space(H5Dget_space(set.get()), H5Sclose, "dataspace of " + path);
    const hssize_t n = H5Sget_simple_extent_npoints(space.get());
    check(static_cast<hid_t>(n), "size of " + path);
    std::vector<T> out(static_cast<std::size_t>(n));
    if (n > 0) check(H5Dread(set.get(), memtype, H5S_ALL, H5S_ALL, dxpl, out.data()), "read " + path);
    return out;
}

}  // namespace jamsim::h5

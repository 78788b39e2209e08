#pragma once
#include <hdf5.h>

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

/// Check an HDF5 return value (negative = failure).
inline hid_t check(hid_t id, const std::string& what) {
    if (id < 0) throw Error("HDF5: " + what + " failed");
    return id;
}

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
            check(rc, "close " + what);
        }
    }

  private:
    void reset() noexcept {
        if (id_ >= 0) close_(std::exchange(id_, H5I_INVALID_HID));
    }
    hid_t id_ = H5I_INVALID_HID;
    Closer close_ = nullptr;
};

/// Silence HDF5's automatic error stack printing: jamsim reports errors itself.
void quiet_errors();

/// New file (truncating), serial driver.
Handle create_file(const std::string& path);
/// Existing file, read-only, serial driver.
Handle open_file_readonly(const std::string& path);
Handle create_group(hid_t parent, const std::string& name);

void write_attribute(hid_t obj, const std::string& name, double value);
void write_attribute(hid_t obj, const std::string& name, std::int64_t value);
void write_attribute(hid_t obj, const std::string& name, const std::string& value);

/// 1-D dataset of doubles with "units" and "description" attributes.
void write_dataset(hid_t parent, const std::string& name, std::span<const double> values,
                   const std::string& units, const std::string& description);

std::vector<double> read_dataset(hid_t parent, const std::string& name);
double read_double_attribute(hid_t obj, const std::string& name);

} // namespace jamsim::h5

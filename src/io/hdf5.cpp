#include "jamsim/io/hdf5.hpp"

#include <vector>

namespace jamsim::h5 {

void quiet_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

Handle create_file(const std::string& path) {
    // Semi close degree: H5Fclose fails (instead of silently deferring) if any object in
    // the file is still open, so a successful close means the file is complete.
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, "file access properties");
    check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_SEMI), "set close degree");
    return Handle(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose,
                  "create file '" + path + "'");
}

Handle open_file_readonly(const std::string& path) {
    return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose,
                  "open file '" + path + "'");
}

Handle create_group(hid_t parent, const std::string& name) {
    return Handle(H5Gcreate2(parent, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                  H5Gclose, "create group '" + name + "'");
}

namespace {
void write_scalar_attribute(hid_t obj, const std::string& name, hid_t type, const void* value) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "scalar dataspace");
    Handle attr(H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
                H5Aclose, "create attribute '" + name + "'");
    check(H5Awrite(attr.get(), type, value), "write attribute '" + name + "'");
    attr.close("attribute '" + name + "'");
}
} // namespace

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

void write_dataset(hid_t parent, const std::string& name, std::span<const double> values,
                   const std::string& units, const std::string& description) {
    const hsize_t dims[1] = {values.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "dataspace for '" + name + "'");
    Handle set(H5Dcreate2(parent, name.c_str(), H5T_NATIVE_DOUBLE, space.get(), H5P_DEFAULT,
                          H5P_DEFAULT, H5P_DEFAULT),
               H5Dclose, "create dataset '" + name + "'");
    if (!values.empty())
        check(H5Dwrite(set.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
              "write dataset '" + name + "'");
    write_attribute(set.get(), "units", units);
    write_attribute(set.get(), "description", description);
    set.close("dataset '" + name + "'");
}

std::vector<double> read_dataset(hid_t parent, const std::string& name) {
    Handle set(H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose,
               "open dataset '" + name + "'");
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
    Handle attr(H5Aopen(obj, name.c_str(), H5P_DEFAULT), H5Aclose,
                "open attribute '" + name + "'");
    double v = 0.0;
    check(H5Aread(attr.get(), H5T_NATIVE_DOUBLE, &v), "read attribute '" + name + "'");
    return v;
}

} // namespace jamsim::h5

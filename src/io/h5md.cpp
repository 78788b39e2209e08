#include "jamsim/io/h5md.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "jamsim/core/version.hpp"
#include "jamsim/io/hdf5.hpp"

namespace jamsim {

namespace {

using h5::Handle;

/// A dataset of shape `dims` written whole from `data` (memory type = file type).
void write_array(hid_t parent, const std::string& name, hid_t type, std::vector<hsize_t> dims, const void* data) {
    Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose,
                 "dataspace for '" + name + "'");
    Handle set(H5Dcreate2(parent, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose,
               "create dataset '" + name + "'");
    h5::check(H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "write dataset '" + name + "'");
    set.close("dataset '" + name + "'");
}

/// An H5MD time-dependent element with one frame: group `name` with value [1, dims...],
/// step [1] and time [1] (0 for a minimised state, which has no time: MDAnalysis needs one).
void write_element(hid_t parent, const std::string& name, std::vector<hsize_t> dims, const double* values,
                   std::int64_t step, double time) {
    Handle g = h5::create_group(parent, name);
    dims.insert(dims.begin(), 1);
    write_array(g.get(), "value", H5T_NATIVE_DOUBLE, dims, values);
    write_array(g.get(), "step", H5T_NATIVE_INT64, {1}, &step);
    const double t = std::isfinite(time) ? time : 0.0;
    write_array(g.get(), "time", H5T_NATIVE_DOUBLE, {1}, &t);
    g.close("group '" + name + "'");
}

void write_int_attribute_array(hid_t obj, const std::string& name, const std::vector<std::int32_t>& v) {
    const hsize_t dims[1] = {v.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "dataspace of attribute '" + name + "'");
    Handle attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_INT32, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                "create attribute '" + name + "'");
    h5::check(H5Awrite(attr.get(), H5T_NATIVE_INT32, v.data()), "write attribute '" + name + "'");
    attr.close("attribute '" + name + "'");
}

void write_scalar_int32_attribute(hid_t obj, const std::string& name, std::int32_t v) {
    Handle space(H5Screate(H5S_SCALAR), H5Sclose, "scalar dataspace");
    Handle attr(H5Acreate2(obj, name.c_str(), H5T_NATIVE_INT32, space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                "create attribute '" + name + "'");
    h5::check(H5Awrite(attr.get(), H5T_NATIVE_INT32, &v), "write attribute '" + name + "'");
    attr.close("attribute '" + name + "'");
}

/// An attribute holding fixed-length strings (H5MD's box/boundary).
void write_strings_attribute(hid_t obj, const std::string& name, const std::vector<std::string>& v) {
    std::size_t width = 1;
    for (const auto& s : v) width = std::max(width, s.size() + 1);
    std::vector<char> packed(width * v.size(), '\0');
    for (std::size_t i = 0; i < v.size(); ++i) std::memcpy(&packed[i * width], v[i].data(), v[i].size());
    const Handle type = h5::fixed_string_type(width);
    const hsize_t dims[1] = {v.size()};
    Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose, "dataspace of attribute '" + name + "'");
    Handle attr(H5Acreate2(obj, name.c_str(), type.get(), space.get(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose,
                "create attribute '" + name + "'");
    h5::check(H5Awrite(attr.get(), type.get(), packed.data()), "write attribute '" + name + "'");
    attr.close("attribute '" + name + "'");
}

}  // namespace

void write_h5md(const std::string& path, const StoredReplica& r, const std::string& archive,
                const std::string& campaign) {
    h5::quiet_errors();
    h5::FileInMemory file(path);
    const hid_t f = file.get();
    const FinalConfiguration& c = r.final;
    const std::size_t n = c.x.size();
    const double L = c.box_side, gamma = c.box_strain;
    const auto step = static_cast<std::int64_t>(0);
    {
        Handle h5md = h5::create_group(f, "h5md");
        write_int_attribute_array(h5md.get(), "version", {1, 1});
        Handle author = h5::create_group(h5md.get(), "author");
        h5::write_attribute(author.get(), "name", std::string("jamsim export"));
        author.close("group author");
        Handle creator = h5::create_group(h5md.get(), "creator");
        h5::write_attribute(creator.get(), "name", std::string("jamsim"));
        h5::write_attribute(creator.get(), "version", std::string(kVersion));
        creator.close("group creator");
        h5md.close("group h5md");
    }
    {
        Handle particles = h5::create_group(f, "particles");
        Handle all = h5::create_group(particles.get(), "all");
        Handle box = h5::create_group(all.get(), "box");
        write_scalar_int32_attribute(box.get(), "dimension", 3);
        write_strings_attribute(box.get(), "boundary", {"periodic", "periodic", "none"});
        const double edges[9] = {L, 0, 0, gamma * L, L, 0, 0, 0, 1.0};
        write_element(box.get(), "edges", {3, 3}, edges, step, r.time);
        box.close("group box");
        std::vector<double> position(3 * n);
        std::vector<std::int32_t> species(n);
        std::vector<std::int64_t> id(n);
        double small = n > 0 ? c.diameter[0] : 1.0;
        for (double d : c.diameter) small = std::min(small, d);
        for (std::size_t i = 0; i < n; ++i) {
            position[3 * i] = c.x[i] + gamma * c.y[i];
            position[3 * i + 1] = c.y[i];
            position[3 * i + 2] = 0.0;
            species[i] = c.diameter[i] > small ? 1 : 0;
            id[i] = static_cast<std::int64_t>(i);
        }
        write_element(all.get(), "position", {n, 3}, position.data(), step, r.time);
        write_array(all.get(), "species", H5T_NATIVE_INT32, {n}, species.data());
        write_array(all.get(), "id", H5T_NATIVE_INT64, {n}, id.data());
        write_array(all.get(), "diameter", H5T_NATIVE_DOUBLE, {n}, c.diameter.data());
        all.close("group all");
        particles.close("group particles");
    }
    {
        Handle obs = h5::create_group(f, "observables");
        for (const auto& [name, v] : {std::pair{"energy_per_particle", r.energy_per_particle},
                                      {"pressure", r.pressure},
                                      {"shear_stress", r.shear_stress},
                                      {"strain", r.strain}})
            write_element(obs.get(), name, {}, &v, step, r.time);
        obs.close("group observables");
    }
    {
        Handle params = h5::create_group(f, "parameters");
        Handle j = h5::create_group(params.get(), "jamsim");
        h5::write_attribute(j.get(), "archive", archive);
        h5::write_attribute(j.get(), "campaign", campaign);
        h5::write_attribute(j.get(), "replica", r.id);
        h5::write_attribute(j.get(), "model", r.model);
        for (const auto& [name, v] : {std::pair{"N", r.n},
                                      {"phi", r.phi},
                                      {"rate", r.rate},
                                      {"seed", r.seed},
                                      {"size_ratio", r.size_ratio},
                                      {"box_side", L},
                                      {"box_strain", gamma}})
            h5::write_attribute(j.get(), name, v);
        h5::write_attribute(j.get(), "description",
                            std::string("final configuration of a jamsim replica: lab positions x = x_sheared + "
                                        "box_strain y in the cell of edges (L,0,0), (box_strain L, L, 0); the "
                                        "third dimension (0,0,1), z = 0, is a non-periodic layer for readers "
                                        "that need three; units d_s (small diameter), k_e, tau"));
        j.close("group jamsim");
        params.close("group parameters");
    }
    file.write_and_close();
}

}  // namespace jamsim

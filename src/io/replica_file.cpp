#include "jamsim/io/replica_file.hpp"

#include <cstdio>
#include <stdexcept>
#include <filesystem>
#include <variant>
#include <vector>

#include "jamsim/core/version.hpp"
#include "jamsim/io/hdf5.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/io/temporary_file.hpp"

namespace jamsim {

namespace {

/// The parameters the replica's model uses, one attribute each (numbers as float64 or
/// int64, text as strings), as the parameter table names them.
void write_params(hid_t root, const ReplicaParams& p) {
    for (const ParamInfo* info : used_parameters(p)) {
        const std::string key(info->key);
        std::visit([&](const auto& v) { h5::write_attribute(root, key, v); }, get_value(p, *info));
    }
    // The random identity as hex text (a uint64 that int64 attributes cannot hold).
    char hex[24];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(replica_identity(p)));
    h5::write_attribute(root, "identity", std::string(hex));
}

void write_final(hid_t root, const System& sys) {
    const FinalConfiguration fin = final_configuration(sys);
    auto g = h5::create_group(root, "final");
    h5::write_dataset(g.get(), "x", fin.x, "d_s", "sheared x in [0, L); lab x = x + box_strain * y");
    h5::write_dataset(g.get(), "y", fin.y, "d_s", "y in [0, L)");
    h5::write_dataset(g.get(), "diameter", fin.diameter, "d_s", "disk diameter");
    h5::write_attribute(g.get(), "box_side", fin.box_side);
    h5::write_attribute(g.get(), "box_strain", fin.box_strain);
    g.close("group final");
}

}  // namespace

void write_replica_file(const std::string& path, const ReplicaParams& params, const ReplicaResult& result) {
    h5::quiet_errors();
    const std::string tmp = make_temporary_beside(path);
    try {
        h5::FileInMemory file(tmp);
        const hid_t root = file.get();
        write_params(root, params);
        h5::write_attribute(root, "code_version", std::string(kVersion));
        h5::write_attribute(root, "build_flags", std::string(kBuildFlags));
        h5::write_attribute(root, "mean_pressure",
                            mean_after(result.series, &Sample::pressure, params.transient, runs_in_time(params)));
        h5::write_attribute(root, "mean_shear_stress",
                            mean_after(result.series, &Sample::shear_stress, params.transient, runs_in_time(params)));
        h5::write_attribute(root, "force_evaluations", result.force_evaluations);
        h5::write_attribute(root, "neighbor_list_builds", result.list_builds);
        h5::write_attribute(root, "wall_seconds", result.wall_seconds);
        {
            auto ts = h5::create_group(root, "timeseries");
            for (const auto& c : kSampleColumns)
                h5::write_dataset(ts.get(), c.name, result.series.column(c.member), c.units, c.description);
            ts.close("group timeseries");
        }
        write_final(root, result.final_state);
        {
            auto g = h5::create_group(root, "correlation");
            h5::write_dataset(g.get(), "x", result.correlation_x, "d_s",
                              "bin centres: lab x distance within a strip |dy| < 1/2");
            h5::write_dataset(g.get(), "g_y", result.correlation_g, "1",
                              "g_y(x) = <u_y(r) u_y(r + x)>/<u_y^2> over strain >= transient");
            g.close("group correlation");
        }
        file.write_and_close(/*sync=*/true);  // the rename never publishes an unwritten file
        std::filesystem::rename(tmp, path);
    } catch (...) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
    }
}

}  // namespace jamsim

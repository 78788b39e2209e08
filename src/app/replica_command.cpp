#include "replica_command.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "jamsim/dynamics/replica.hpp"
#include "jamsim/io/replica_file.hpp"
#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/observe/time_series.hpp"

namespace jamsim::app {

namespace {

struct ReplicaOptions {
    ReplicaParams params;
    std::string integrator = "euler";
    std::string output;
};

/// One message naming the option, the value and what is allowed; exit code 2.
[[noreturn]] void usage_error(const std::string& key, const std::string& value,
                              const std::string& allowed) {
    throw CLI::ValidationError("jamsim replica: --" + key + " = " + value +
                               " is not allowed: " + allowed);
}

void check_output_path(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        usage_error("output", path, "a file in an existing directory ('" + dir.string() +
                                        "' does not exist)");
    if (::access(dir.c_str(), W_OK) != 0)
        usage_error("output", path, "a file in a writable directory ('" + dir.string() +
                                        "' is not writable)");
    if (fs::is_directory(p, ec)) usage_error("output", path, "a file name, not a directory");
}

void run(const ReplicaOptions& opt) {
    ReplicaParams params = opt.params;
    try {
        params.integrator = integrator_from_string(opt.integrator);
    } catch (const std::invalid_argument&) {
        usage_error("integrator", opt.integrator, "euler or heun");
    }
    for (const auto& e : validate(params)) usage_error(e.key, e.value, e.allowed);
    check_output_path(opt.output);
    const linalg::PetscScope petsc;  // CD0 initialises PETSc on first use; finalise it here

    const ReplicaResult result = run_replica(params);
    write_replica_file(opt.output, params, result);
    const double p = mean_after(result.series, &Sample::pressure, params.transient);
    const double s = mean_after(result.series, &Sample::shear_stress, params.transient);
    const double steps_per_s = static_cast<double>(result.force_evaluations) *
                               static_cast<double>(params.n) / result.wall_seconds;
    std::printf("replica %s N=%lld phi=%.6g rate=%.6g: %zu samples, %.2f s, %.3g particle-force-"
                "evaluations/s\n",
                params.model.c_str(), static_cast<long long>(params.n), params.phi, params.rate,
                result.series.size(), result.wall_seconds, steps_per_s);
    std::printf("mean pressure     <p>     = %.10g\n", p);
    std::printf("mean shear stress <sigma> = %.10g\n", s);
    std::printf("(averages over strain >= %g; written to %s)\n", params.transient,
                opt.output.c_str());
}

} // namespace

CLI::App* add_replica_command(CLI::App& app) {
    auto opt = std::make_shared<ReplicaOptions>();
    ReplicaParams& p = opt->params;
    auto* cmd = app.add_subcommand("replica", "Run one sheared replica and write an HDF5 file");
    cmd->add_option("--model", p.model, "Dynamical model")->capture_default_str();
    cmd->add_option("--N", p.n, "Number of disks")->capture_default_str();
    cmd->add_option("--phi", p.phi, "Packing fraction")->capture_default_str();
    cmd->add_option("--rate", p.rate, "Shear rate (1/tau)")->capture_default_str();
    cmd->add_option("--strain", p.strain, "Total strain (when rate > 0)")->capture_default_str();
    cmd->add_option("--time", p.time, "Total time in tau (when rate = 0)")->capture_default_str();
    cmd->add_option("--transient", p.transient, "Strain excluded from the printed averages")
        ->capture_default_str();
    cmd->add_option("--sample-interval", p.sample_interval,
                    "Strain between samples (time when rate = 0)")
        ->capture_default_str();
    cmd->add_option("--dt", p.dt, "Time step (tau)")->capture_default_str();
    cmd->add_option("--alpha", p.alpha, "Potential exponent (2 harmonic, 2.5 Hertzian)")
        ->capture_default_str();
    cmd->add_option("--size-ratio", p.size_ratio, "Large/small diameter (1 = monodisperse)")
        ->capture_default_str();
    cmd->add_option("--skin", p.skin, "Neighbour-list skin (d_s)")->capture_default_str();
    cmd->add_option("--kd", p.kd, "Dissipation coefficient k_d")->capture_default_str();
    cmd->add_option("--delta", p.delta, "CD0 substrate drag delta = k_0/k_d")
        ->capture_default_str();
    cmd->add_option("--mass", p.mass, "Small-disk mass (RD, CD, CDn, CDt)")->capture_default_str();
    cmd->add_option("--solver", p.solver, "CD0 backend: auto (eigen up to N = 65536, petsc above), petsc (KSP) or eigen (sparse LDLT)")
        ->capture_default_str();
    cmd->add_option("--petsc-options", p.petsc_options,
                    "CD0 solver options, e.g. \"-cd0_pc_type icc -cd0_ksp_rtol 1e-8\"");
    cmd->add_option("--integrator", opt->integrator, "euler or heun")->capture_default_str();
    cmd->add_option("--minimizer", p.minimizer, "static models: cg, cg-pr or fire")->capture_default_str();
    cmd->add_option("--strain-step", p.strain_step, "QS: strain step between minimisations")
        ->capture_default_str();
    cmd->add_option("--energy-floor", p.energy_floor, "E/N below which a minimised state is unjammed")
        ->capture_default_str();
    cmd->add_option("--force-tol", p.force_tol, "force balance relative to the mean contact force")
        ->capture_default_str();
    cmd->add_option("--force-tol-abs", p.force_tol_abs, "force balance floor (k_e/d_s)")
        ->capture_default_str();
    cmd->add_option("--phi-tol", p.phi_tol, "COMPRESS: width of the final phi_J bracket")
        ->capture_default_str();
    cmd->add_option("--temperature", p.temperature, "COOL: starting temperature (k_e)")->capture_default_str();
    cmd->add_option("--cooling-time", p.cooling_time, "COOL: time over which T falls linearly to 0")
        ->capture_default_str();
    cmd->add_option("--seed", p.seed, "Random seed")->capture_default_str();
    cmd->add_option("--replica", p.replica, "Replica id (part of the random key)")
        ->capture_default_str();
    cmd->add_option("-o,--output", opt->output, "Output HDF5 file")->required();
    cmd->callback([opt] { run(*opt); });
    return cmd;
}

} // namespace jamsim::app

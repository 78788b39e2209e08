// `jamsim minimize`: one RAND configuration minimised, with the figures a benchmark needs
// (iterations, force evaluations, final E/N, largest force component, pressure, time), and
// optionally the start configuration as a LAMMPS data file so that another code can minimise
// the very same configuration.
#include "minimize_command.hpp"
#include "option_checks.hpp"
#include "threads_option.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "jamsim/archive/capacity.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/force/force_field.hpp"
#include "jamsim/minimize/minimizer.hpp"
#include "jamsim/params/parameters.hpp"
#include "jamsim/run/model_registry.hpp"
#include "jamsim/io/temporary_file.hpp"

namespace jamsim::app {

namespace {

struct Options {
    std::int64_t n = 1024;
    double phi = 0.85;
    std::uint64_t seed = 1;
    std::string minimizer = "cg";
    double alpha = 2.0;
    MinimizeCriteria criteria;
    std::string lammps_data;
};

/// The start configuration as a LAMMPS `atom_style atomic` data file: type 1 = small
/// (d = 1), type 2 = large (d = size ratio); orthogonal cell [0, L)², unit masses.
void write_lammps_data(const System& sys, const std::string& path) {
    // Written beside it and renamed: a full disk leaves no partial file under the name.
    const std::string tmp = make_temporary_beside(path);
    std::ofstream out(tmp);
    if (!out) {
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw std::runtime_error("cannot write LAMMPS data file '" + path + "'");
    }
    const Particles& p = sys.particles;
    const double L = sys.box.side();
    char line[256];
    out << "LAMMPS data file: jamsim RAND start configuration\n\n" << p.size() << " atoms\n2 atom types\n\n";
    std::snprintf(line, sizeof line, "0 %.17g xlo xhi\n0 %.17g ylo yhi\n-0.5 0.5 zlo zhi\n\n", L, L);
    out << line << "Masses\n\n1 1.0\n2 1.0\n\nAtoms # atomic\n\n";
    for (std::size_t i = 0; i < p.size(); ++i) {
        double x = p.x[i], y = p.y[i];
        sys.box.wrap_into_cell(x, y);
        std::snprintf(line, sizeof line, "%lld %d %.17g %.17g 0\n", static_cast<long long>(p.tag[i]) + 1,
                      p.diameter[i] > 1.0 ? 2 : 1, x, y);
        out << line;
    }
    out.close();
    std::error_code ec;
    if (!out) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("writing LAMMPS data file '" + path + "' failed (no space left on the device?)");
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot rename '" + tmp + "' to '" + path + "'");
    }
}

}  // namespace

namespace {

/// The options as the parameters of one RAND replica, checked by the campaign keys' own rules
/// (src/params/parameters.cpp, validate): the stopping rule, the exponent, the minimiser, and a
/// box the neighbour list can cover. Each refusal names the option; exit status 2.
void check_options(const Options& opt) {
    ReplicaParams p;
    p.model = "RAND";
    p.n = opt.n;
    p.phi = opt.phi;
    p.seed = opt.seed;
    p.alpha = opt.alpha;
    p.minimizer = opt.minimizer;
    p.energy_floor = opt.criteria.energy_floor;
    p.force_tol = opt.criteria.force_tol;
    p.force_tol_abs = opt.criteria.force_tol_abs;
    for (const auto& e : validate(p)) {
        const ParamInfo* info = find_parameter(e.key);
        throw CLI::ValidationError("jamsim minimize: " + (info ? std::string(info->flag) : e.key) + " = " + e.value +
                                   " is not allowed: " + e.allowed);
    }
    if (const std::string too_large = check_replica_memory(p); !too_large.empty())
        throw CLI::ValidationError("jamsim minimize: " + too_large);
    for (const auto& [kind, text] : advisories(p)) std::fprintf(stderr, "jamsim minimize: warning: %s\n", text.c_str());
    // Not a campaign key: the campaign's minimisations take their own limit.
    if (opt.criteria.max_iterations < 1)
        throw CLI::ValidationError(
            "jamsim minimize: --max-iterations = " + std::to_string(opt.criteria.max_iterations) +
            " is not allowed: a whole number >= 1");
}

}  // namespace

CLI::App* add_minimize_command(CLI::App& app) {
    auto opt = std::make_shared<Options>();
    auto* cmd = app.add_subcommand("minimize", "Minimise one random (RAND) configuration and report the cost");
    cmd->add_option("--N", opt->n, "Number of disks (even)")->check(whole_number())->capture_default_str();
    cmd->add_option("--phi", opt->phi, "Packing fraction")->check(decimal_number())->capture_default_str();
    cmd->add_option("--seed", opt->seed, "Random seed")->check(whole_number())->capture_default_str();
    cmd->add_option("--minimizer", opt->minimizer, "cg (default), cg-pr or fire")->capture_default_str();
    cmd->add_option("--alpha", opt->alpha, "Potential exponent (2 harmonic, 2.5 Hertzian)")
        ->check(decimal_number())
        ->capture_default_str();
    cmd->add_option("--energy-floor", opt->criteria.energy_floor, "E/N below which the state is unjammed")
        ->check(decimal_number())
        ->capture_default_str();
    cmd->add_option("--force-tol", opt->criteria.force_tol, "largest force component / mean contact force")
        ->check(decimal_number())
        ->capture_default_str();
    cmd->add_option("--force-tol-abs", opt->criteria.force_tol_abs, "largest force component, absolute (k_e/d_s)")
        ->check(decimal_number())
        ->capture_default_str();
    cmd->add_option("--max-iterations", opt->criteria.max_iterations, "Give up after this many iterations")
        ->check(count_at_least_one("iterations"))
        ->capture_default_str();
    cmd->add_flag_callback(
        "--no-split", [opt] { opt->criteria.split_positions = false; },
        "Plain positions instead of base + offset (for comparison)");
    cmd->add_option("--lammps-data", opt->lammps_data, "Also write the start configuration here (LAMMPS data file)")
        ->check(nonempty_path())
        ->type_name("FILE");
    cmd->callback([opt, cmd] {
        refuse_more_than_one_process("jamsim minimize");
        check_threads_environment("jamsim minimize", false);
        // The values as written (the messages said only what is allowed).
        const auto as_written = [cmd](const char* name) {
            const auto written = cmd->get_option(name)->results();
            return written.empty() ? std::string("its default") : written.back();
        };
        if (opt->n < 8 || opt->n % 2)
            throw CLI::ValidationError("jamsim minimize: --N = " + as_written("--N") +
                                       " is not allowed: an even number >= 8");
        if (!(opt->phi > 0 && opt->phi < 1))
            throw CLI::ValidationError("jamsim minimize: --phi = " + as_written("--phi") +
                                       " is not allowed: 0 < phi < 1");
        check_options(*opt);
        if (!opt->lammps_data.empty())
            if (const std::string why = writable_new_file(opt->lammps_data); !why.empty())
                throw CLI::ValidationError("jamsim minimize: --lammps-data = " + opt->lammps_data +
                                           " is not allowed: " + why);
        if (std::error_code ec; !opt->lammps_data.empty() && std::filesystem::exists(opt->lammps_data, ec))
            throw CLI::ValidationError("jamsim minimize: --lammps-data = " + opt->lammps_data +
                                       " is not allowed: a new file (it exists, and jamsim minimize does not "
                                       "overwrite; remove it or choose another name)");
        auto minimizer = make_minimizer(opt->minimizer);
        System sys = random_system(opt->n, opt->phi, SizeMix{}, opt->seed, 0);
        if (!opt->lammps_data.empty()) write_lammps_data(sys, opt->lammps_data);
        ForceField ff(potential::make_soft_sphere(opt->alpha), 0.3);
        const auto t0 = std::chrono::steady_clock::now();
        const MinimizeResult r = minimizer->minimize(sys, ff, opt->criteria);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("RESULT N=%lld phi=%g seed=%llu minimizer=%s outcome=%s iterations=%lld "
                    "force_evaluations=%lld E/N=%.6e fmax=%.3e fbar=%.3e P=%.10e seconds=%.4f "
                    "particle_iterations_per_s=%.3e list_builds=%zu\n",
                    static_cast<long long>(opt->n), opt->phi, static_cast<unsigned long long>(opt->seed),
                    opt->minimizer.c_str(), std::string(to_string(r.outcome)).c_str(),
                    static_cast<long long>(r.iterations), static_cast<long long>(r.force_evaluations),
                    r.energy_per_particle, r.max_force, r.mean_contact_force, r.pressure, seconds,
                    static_cast<double>(r.iterations) * static_cast<double>(opt->n) / seconds, ff.builds());
        if (r.outcome == MinimizeOutcome::NotConverged) throw std::runtime_error("minimisation did not converge");
    });
    return cmd;
}

}  // namespace jamsim::app

#include "jamsim/params/parameters.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "jamsim/linalg/contact_solver.hpp"
#include "jamsim/minimize/minimizer.hpp"

namespace jamsim {

namespace {

using R = ReplicaParams;
constexpr auto kPhys = Identity::Physics;
constexpr auto kNum = Identity::Numerics;

bool positive(double v) { return std::isfinite(v) && v > 0.0; }
bool non_negative(double v) { return std::isfinite(v) && v >= 0.0; }

// Checks: "" when usable, else what is allowed (the row's `allowed` when it says it all).
#define JAMSIM_CHECK(cond, text) [](const R& p) -> std::string { return (cond) ? "" : (text); }

std::string check_n(const R& p) {
    if (p.n < 2) return "an integer >= 2";
    if (p.size_ratio != 1.0 && p.n % 2 != 0) return "an even number (50:50 mixture; size_ratio = 1 allows odd N)";
    return "";
}

std::string check_minimizer(const R& p) {
    const auto names = minimizer_names();
    if (std::find(names.begin(), names.end(), p.minimizer) != names.end()) return "";
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    return list;
}

std::string check_force_tol(const R& p) {
    // A ratio to the mean contact force: at 1 or more a random start counts as balanced.
    if (!non_negative(p.force_tol) || p.force_tol >= 1.0) return "0 <= force_tol < 1";
    if (p.force_tol == 0.0 && p.force_tol_abs == 0.0)
        return "force_tol > 0 or force_tol_abs > 0 (a reachable stopping rule)";
    return "";
}

// PETSc options must reach a PETSc solver (CD0's backend, chosen by `solver` and N) and carry
// its prefix; whether PETSc recognises them is checked where PETSc runs
// (linalg::petsc_options_problem, before a run starts).
std::string check_petsc_options(const R& p) {
    if (p.petsc_options.empty()) return "";
    if (p.solver == "eigen" || p.solver == "cholmod")
        return "none with solver = " + p.solver + " (the " + p.solver +
               " backend reads no PETSc options; choose solver = petsc to use them)";
    if (p.solver == "auto" && linalg::resolve_backend("auto", static_cast<std::size_t>(p.n)) != "petsc")
        return "none with solver = auto at N = " + std::to_string(p.n) + " (auto uses " +
               std::string(linalg::resolve_backend("auto", static_cast<std::size_t>(p.n))) +
               ", which reads no PETSc options; choose solver = petsc to use them)";
    std::string prefix = "-";  // appended, not "-" + ...: GCC 12 warns falsely (-Wrestrict)
    prefix.append(linalg::kPetscPrefix);
    for (const auto& name : linalg::petsc_option_names(p.petsc_options))
        if (name.rfind(prefix, 0) != 0) {
            std::string out = "options with the CD0 solver's prefix ";
            out.append(prefix).append(" (").append(name).append(" has none: ").append(prefix);
            out.append(name.substr(1)).append("?)");
            return out;
        }
    return "";
}

// The table. Order: identity of the replica, run length and sampling, the model's
// parameters, minimisation, potential, system.
const ParamInfo kParameters[] = {
    {"model", "model", "name", "--model", "", "model or protocol", &R::model, kPhys, nullptr,
     "a registered model (jamsim models)"},
    {"N", "sweep", "N", "--N", "1", "number of disks", &R::n, kPhys, check_n,
     "an integer >= 2, even unless size_ratio = 1"},
    {"phi", "sweep", "phi", "--phi", "1", "packing fraction sum(pi d_i^2/4) / L^2", &R::phi, kPhys,
     JAMSIM_CHECK(p.phi > 0.0 && p.phi < 1.0, "0 < phi < 1"), "0 < phi < 1"},
    {"rate", "sweep", "rate", "--rate", "1/tau", "shear rate", &R::rate, kPhys,
     JAMSIM_CHECK(non_negative(p.rate), "rate >= 0"), "rate >= 0"},
    {"seed", "sweep", "seeds", "--seed", "1",
     "random seed; with the replica's physical parameters it keys every random number", &R::seed, kPhys, nullptr,
     "an integer >= 0 (in a campaign: a count or a list)"},
    {"strain", "run", "strain", "--strain", "1",
     "total strain (dynamics at rate > 0; QS and SHEARED: strain of the quasistatic shear)", &R::strain, kNum,
     JAMSIM_CHECK(positive(p.strain), "strain > 0"), "strain > 0"},
    {"time", "run", "time", "--time", "tau", "total time of a dynamics run at rate 0", &R::time, kNum,
     JAMSIM_CHECK(positive(p.time), "time > 0 (needed when rate = 0)"), "time > 0"},
    {"transient", "run", "transient", "--transient", "1", "strain (time at rate 0) excluded from averages and g_y",
     &R::transient, kNum, JAMSIM_CHECK(non_negative(p.transient), "transient >= 0"), "transient >= 0"},
    {"sample_interval", "run", "sample_interval", "--sample-interval", "1",
     "strain (time at rate 0) between samples, rounded to whole steps", &R::sample_interval, kNum,
     JAMSIM_CHECK(positive(p.sample_interval), "sample_interval > 0"), "sample_interval > 0"},
    {"frame_interval", "run", "frame_interval", "", "1",  // campaigns only: frames live in the archive
     "strain (time at rate 0) between configuration frames kept in the archive (/frames), "
     "rounded to whole steps; 0: none",
     &R::frame_interval, kNum, JAMSIM_CHECK(non_negative(p.frame_interval), "frame_interval >= 0"),
     "frame_interval >= 0 (0: no frames)"},
    {"checkpoint_steps", "run", "checkpoint_steps", "--checkpoint-steps", "steps",
     "steps (QS, SHEARED: strain steps; COOL: cooling steps) between checkpoint steps, where "
     "the run drops its kernel caches and may save its state",
     &R::checkpoint_steps, kNum, JAMSIM_CHECK(p.checkpoint_steps >= 1, "checkpoint_steps >= 1"), "an integer >= 1"},
    {"rate_ladder", "sweep", "rate_ladder", "", "",  // campaigns only: it links replicas
     "\"down\": for each N, phi and seed the rates run from high to low, each replica starting "
     "from the end state of the next higher rate (transients cut as by Olsson and Teitel)",
     &R::rate_ladder, kPhys, JAMSIM_CHECK(p.rate_ladder.empty() || p.rate_ladder == "down", "\"down\" or \"\""),
     "\"\", down"},
    {"ladder_from", "", "", "", "1/tau",
     "rate ladders: the rate of the replica whose end state starts this one (0: random start)", &R::ladder_from, kPhys,
     nullptr, "derived from the sweep"},
    {"initial", "run", "initial", "--initial", "",
     "campaign archive whose finished replicas' final states are the initial configurations, "
     "or a LAMMPS data file (as jamsim export writes) that starts every replica (relative to "
     "the working directory; \"\": random positions)",
     &R::initial, kPhys, nullptr, "a campaign archive or a LAMMPS data file"},
    {"initial_match", "run", "initial_match", "--initial-match", "",
     "which replica of the initial archive starts each replica: parameters (the same N, phi "
     "and seed) or id (the same replica id; positions scaled affinely to phi)",
     &R::initial_match, kPhys,
     JAMSIM_CHECK(p.initial_match == "parameters" || p.initial_match == "id", "parameters or id"), "parameters, id"},
    {"dt", "model", "dt", "--dt", "tau", "time step", &R::dt, kNum, JAMSIM_CHECK(positive(p.dt), "dt > 0"),
     "dt > 0 (and below the model's stable limit)"},
    {"integrator", "model", "integrator", "--integrator", "",
     "overdamped models: euler (1 force evaluation per step) or heun (2, second order)", &R::integrator, kNum,
     JAMSIM_CHECK(p.integrator == "euler" || p.integrator == "heun", "euler or heun"), "euler, heun"},
    {"kd", "model", "kd", "--kd", "k_e tau/d_s^2", "dissipation coefficient k_d", &R::kd, kPhys,
     JAMSIM_CHECK(positive(p.kd), "kd > 0"), "kd > 0"},
    {"mass", "model", "mass", "--mass", "k_e tau^2/d_s^2", "mass of a small disk (large disks scale by area)", &R::mass,
     kPhys, JAMSIM_CHECK(positive(p.mass), "mass > 0"), "mass > 0"},
    {"delta", "model", "delta", "--delta", "1", "CD0 substrate drag k_0/k_d on the non-affine velocity", &R::delta,
     kPhys, JAMSIM_CHECK(positive(p.delta), "delta > 0"), "delta > 0"},
    {"solver", "model", "solver", "--solver", "",
     "CD0 backend: auto (petsc at every N), petsc (KSP preconditioned by a CHOLMOD LDLT updated in place; PETSc "
     "options choose others), cholmod (that LDLT alone) or eigen (Eigen LDLT updated in place)",
     &R::solver, kNum,
     JAMSIM_CHECK(p.solver == "auto" || p.solver == "cholmod" || p.solver == "petsc" || p.solver == "eigen",
                  "auto, cholmod, petsc or eigen"),
     "auto, cholmod, petsc, eigen"},
    {"petsc_options", "model", "petsc_options", "--petsc-options", "",
     "CD0 PETSc options with prefix cd0_, e.g. \"-cd0_pc_type icc\"", &R::petsc_options, kNum, check_petsc_options,
     "PETSc options"},
    {"temperature", "model", "temperature", "--temperature", "k_e",
     "temperature (COOL, COOL_COMPRESS: the starting temperature T_0)", &R::temperature, kPhys,
     JAMSIM_CHECK(positive(p.temperature), "temperature > 0"), "temperature > 0"},
    {"cooling_time", "model", "cooling_time", "--cooling-time", "tau", "time over which T falls linearly to 0",
     &R::cooling_time, kPhys, JAMSIM_CHECK(positive(p.cooling_time), "cooling_time > 0"), "cooling_time > 0"},
    {"minimizer", "model", "minimizer", "--minimizer", "",
     "cg (hybrid HS/DY), cg-pr (Polak-Ribiere) or fire (FIRE 2.0)", &R::minimizer, kNum, check_minimizer,
     "cg, cg-pr, fire"},
    {"strain_step", "model", "strain_step", "--strain-step", "1", "quasistatic shear: strain between minimisations",
     &R::strain_step, kNum, JAMSIM_CHECK(positive(p.strain_step), "strain_step > 0"), "strain_step > 0"},
    {"energy_floor", "model", "energy_floor", "--energy-floor", "k_e", "minimisation: E/N below this is unjammed",
     // Below 1e-2: E/N = 1e-2 k_e means overlaps of about a seventh of a diameter, deep in a
     // jammed packing (energy_floor = 1e300 called every state unjammed).
     &R::energy_floor, kNum, JAMSIM_CHECK(positive(p.energy_floor) && p.energy_floor < 1e-2, "0 < energy_floor < 0.01"),
     "0 < energy_floor < 0.01"},
    {"force_tol", "model", "force_tol", "--force-tol", "1",
     "minimisation: largest force component / mean contact force at convergence", &R::force_tol, kNum, check_force_tol,
     "0 <= force_tol < 1"},
    {"force_tol_abs", "model", "force_tol_abs", "--force-tol-abs", "k_e/d_s",
     "minimisation: absolute force floor at convergence", &R::force_tol_abs, kNum,
     // Below k_e/d_s, the force of a full overlap.
     JAMSIM_CHECK(non_negative(p.force_tol_abs) && p.force_tol_abs < 1.0, "0 <= force_tol_abs < 1"),
     "0 <= force_tol_abs < 1"},
    {"phi_tol", "model", "phi_tol", "--phi-tol", "1", "phi_J search: width of the final bracket", &R::phi_tol, kNum,
     JAMSIM_CHECK(p.phi_tol >= 1e-14 && p.phi_tol < 1e-2, "1e-14 <= phi_tol < 0.01"), "1e-14 <= phi_tol < 0.01"},
    {"alpha", "potential", "alpha", "--alpha", "1",
     "potential exponent: V = k_e/alpha (1 - r/d)^alpha ([potential] name = harmonic: 2, "
     "hertzian: 2.5)",
     // At most 20: overlaps of 1e-8 (near jamming) give energies of 1e-160, far from double's
     // underflow; alpha = 1e300 ran with every force 0 and no word.
     &R::alpha, kPhys, JAMSIM_CHECK(std::isfinite(p.alpha) && p.alpha > 1.0 && p.alpha <= 20.0, "1 < alpha <= 20"),
     "1 < alpha <= 20"},
    {"size_ratio", "system", "size_ratio", "--size-ratio", "1",
     "large/small diameter of the 50:50 mixture (1: monodisperse)", &R::size_ratio, kPhys,
     // At most 100: g_y's bins and the cell list's cells grow with the large disks' size, and
     // a size_ratio of 1e10 (a typo) was refused only for the disk space its bins would take.
     JAMSIM_CHECK(std::isfinite(p.size_ratio) && p.size_ratio >= 1.0 && p.size_ratio <= 100.0,
                  "1 <= size_ratio <= 100"),
     "1 <= size_ratio <= 100"},
    {"skin", "system", "skin", "--skin", "d_s",
     "neighbour-list skin (CD0's contact matrix: candidate pairs within skin/3)", &R::skin, kNum,
     JAMSIM_CHECK(positive(p.skin), "skin > 0"), "skin > 0"},
};
#undef JAMSIM_CHECK

}  // namespace

std::span<const ParamInfo> parameters() { return kParameters; }

const ParamInfo* find_parameter(std::string_view key) {
    for (const auto& info : kParameters)
        if (info.key == key) return &info;
    return nullptr;
}

ParamValue get_value(const ReplicaParams& p, const ParamInfo& info) {
    return std::visit(
        [&](auto member) -> ParamValue {
            const auto& v = p.*member;
            using T = std::decay_t<decltype(v)>;
            if constexpr (std::is_same_v<T, std::uint64_t>)
                return static_cast<std::int64_t>(v);
            else
                return v;
        },
        info.field);
}

bool set_value(ReplicaParams& p, const ParamInfo& info, const ParamValue& value) {
    return std::visit(
        [&](auto member) -> bool {
            auto& target = p.*member;
            using T = std::decay_t<decltype(target)>;
            if constexpr (std::is_same_v<T, std::string>) {
                if (const auto* s = std::get_if<std::string>(&value)) return target = *s, true;
            } else if constexpr (std::is_same_v<T, double>) {
                // -0 is 0: a rate of -0 was a replica of its own beside rate 0 (and stored as -0).
                if (const auto* d = std::get_if<double>(&value)) return target = *d == 0.0 ? 0.0 : *d, true;
                if (const auto* i = std::get_if<std::int64_t>(&value)) return target = static_cast<double>(*i), true;
            } else {  // integers
                if (const auto* i = std::get_if<std::int64_t>(&value)) {
                    if (std::is_unsigned_v<T> && *i < 0) return false;
                    return target = static_cast<T>(*i), true;
                }
            }
            return false;
        },
        info.field);
}

bool is_numeric(const ParamInfo& info) { return !std::holds_alternative<std::string ReplicaParams::*>(info.field); }

std::string value_kind(const ParamInfo& info) {
    return std::visit(
        [](auto member) -> std::string {
            using T = std::decay_t<decltype(ReplicaParams{}.*member)>;
            if constexpr (std::is_same_v<T, std::string>)
                return "a string";
            else if constexpr (std::is_same_v<T, double>)
                return "a number";
            else if constexpr (std::is_unsigned_v<T>)  // stored as a signed 64-bit integer
                return "a whole number from 0 to 9223372036854775807";
            else
                return "an integer";
        },
        info.field);
}

double numeric_value(const ReplicaParams& p, const ParamInfo& info) {
    const ParamValue v = get_value(p, info);
    if (const auto* d = std::get_if<double>(&v)) return *d;
    if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
    return std::nan("");
}

std::string show_value(const ParamValue& value) {
    if (const auto* s = std::get_if<std::string>(&value)) return *s;
    if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
    const double d = std::get<double>(value);
    // Shortest of 15 or 17 significant digits that reads back to the same double.
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.15g", d);
    if (std::strtod(buf, nullptr) != d) std::snprintf(buf, sizeof buf, "%.17g", d);
    return buf;
}

std::string show_in_message(const ParamValue& value) {
    const auto* s = std::get_if<std::string>(&value);
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    if (!s || (!s->empty() && !space(s->front()) && !space(s->back()))) return show_value(value);
    return "\"" + *s + "\"";
}

std::string default_text(const ParamInfo& info) { return show_value(get_value(ReplicaParams{}, info)); }

bool parse_value(const ParamInfo& info, const std::string& text, ParamValue& out) {
    if (!is_numeric(info)) return out = text, true;
    // Decimal only, as in a campaign file (std::from_chars, as core/parse_number.hpp, which this
    // layer lies below: strtod read --phi 0x1p-1 as 0.5 and skipped a leading space); a leading
    // '+' is taken, as it was.
    std::string_view digits = text;
    if (digits.starts_with('+') && digits.size() > 1 && digits[1] != '-') digits.remove_prefix(1);
    const auto whole = [digits](auto& value) {
        const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        return ec == std::errc{} && end == digits.data() + digits.size();
    };
    if (std::holds_alternative<double ReplicaParams::*>(info.field)) {
        double d = 0.0;
        return whole(d) && (out = d, true);
    }
    std::int64_t i = 0;
    return whole(i) && (out = i, true);
}

}  // namespace jamsim

#include "jamsim/run/model_registry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "jamsim/core/system.hpp"
#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/dynamics/sllod.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/observe/time_series.hpp"
#include "jamsim/protocols/preparation.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

DynamicsInfo thermal_rd0_model();  // src/dynamics/thermal_rd0.cpp

// Minimisation protocols (src/run/static_protocols.cpp).
ModelInfo qs_protocol();
ModelInfo rand_protocol();
ModelInfo compress_protocol();
ModelInfo cool_protocol();
ModelInfo cool_compress_protocol();
ModelInfo sheared_protocol();

namespace {

Schedule dynamics_schedule(const ReplicaParams& p) {
    const double duration = p.rate > 0.0 ? p.strain / p.rate : p.time;
    const double sample_time = p.rate > 0.0 ? p.sample_interval / p.rate : p.sample_interval;
    const double frame_time = p.rate > 0.0 ? p.frame_interval / p.rate : p.frame_interval;
    return {.steps = static_cast<std::int64_t>(std::ceil(duration / p.dt - 1e-9)),
            .sample_every = std::max<std::int64_t>(1, std::llround(sample_time / p.dt)),
            .frame_every = p.frame_interval > 0.0 ? std::max<std::int64_t>(1, std::llround(frame_time / p.dt)) : 0};
}

/// A dynamical model's registration as the run layer sees it.
ModelInfo dynamics(const DynamicsInfo& d) {
    return {.name = d.name,
            .kind = ModelKind::Dynamics,
            .summary = d.summary,
            .parameters = d.parameters,
            .evaluations_per_step = d.evaluations_per_step,
            .stable_dt = d.stable_dt,
            .schedule = dynamics_schedule,
            .cost =
                [](const ReplicaParams& p) {
                    return static_cast<double>(p.n) * static_cast<double>(dynamics_schedule(p).steps) *
                           evaluations_per_step(p);
                },
            .run = run_dynamics,
            .make = d.make,
            .extendable = true,
            .bytes_per_disk = d.bytes_per_disk,
            .stable_dt_basis = d.stable_dt_basis,
            .advisory = d.advisory,
            .relax_start = d.relax_start,
            .thread_scaling = d.thread_scaling};
}

/// One line per model or protocol: adding one is its own file plus a line here.
const std::vector<ModelInfo>& registry() {
    static const std::vector<ModelInfo> all{
        dynamics(rd0_model()),
        dynamics(cd0_model()),
        dynamics(rd_model()),
        dynamics(cd_model()),
        dynamics(cdn_model()),
        dynamics(cdt_model()),
        dynamics(thermal_rd0_model()),
        qs_protocol(),
        rand_protocol(),
        compress_protocol(),
        cool_protocol(),
        cool_compress_protocol(),
        sheared_protocol(),
    };
    return all;
}

constexpr std::string_view kCommonParameters[] = {"model", "N", "phi", "seed", "alpha", "size_ratio", "skin"};

bool contains(std::span<const std::string_view> keys, std::string_view key) {
    return std::find(keys.begin(), keys.end(), key) != keys.end();
}

/// FNV-1a over the text, then the splitmix64 finaliser (full avalanche of all 64 bits).
std::uint64_t hash64(std::string_view text) {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ull;
    h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
    h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
    return h ^ (h >> 31);
}

/// The run length a replica's transient and sampling are measured against: strain (rate > 0,
/// and the quasistatic protocols) or time (dynamics at rate 0); key nullptr when it has none.
struct RunLength {
    const char* key = nullptr;
    double value = 0.0;
};
RunLength run_length(const ReplicaParams& p) {
    if (uses_parameter(p, "strain")) return {"strain", p.strain};
    if (uses_parameter(p, "time")) return {"time", p.time};
    return {};
}

/// The samples at or after the transient (both ends of the run are sampled), and the run
/// length (strain or time) of the last sample; for a valid p whose model samples.
struct SamplesAfterTransient {
    std::int64_t count = 0;
    double last = 0.0;
};
SamplesAfterTransient samples_after_transient(const ReplicaParams& p, const Schedule& s, const RunLength& run) {
    const double per_sample = run.value / static_cast<double>(s.steps) * static_cast<double>(s.sample_every);
    const std::int64_t last = s.steps / s.sample_every;
    const auto first = static_cast<std::int64_t>(std::ceil(p.transient / per_sample - 1e-9));
    return {std::max<std::int64_t>(0, last - first + 1), static_cast<double>(last) * per_sample};
}

/// Potential exponents below this make energy minimisations slow or non-convergent (advisories).
constexpr double kSlowMinimizationAlpha = 1.5;
/// Fewer samples than this after the transient: averages from so few are worth a warning.
constexpr std::int64_t kFewSamples = 10;

}  // namespace

std::span<const ModelInfo> models() { return registry(); }

const ModelInfo* find_model(std::string_view name) {
    for (const auto& m : registry())
        if (m.name == name) return &m;
    return nullptr;
}

std::string model_list() {
    std::string list;
    for (const auto& m : registry()) list += (list.empty() ? "" : ", ") + std::string(m.name);
    return list;
}

const ModelInfo& model_of(const ReplicaParams& p) {
    if (const ModelInfo* m = find_model(p.model)) return *m;
    throw std::invalid_argument("unknown model '" + p.model + "' (known: " + model_list() + ")");
}

bool uses_parameter(const ReplicaParams& p, std::string_view key) {
    if (contains(kCommonParameters, key)) return true;
    if (key == "initial") return !p.initial.empty();  // recorded only when set
    if (key == "initial_match") return !p.initial.empty();
    const ModelInfo* m = find_model(p.model);
    if (!m) return false;
    if (m->kind == ModelKind::Dynamics) {
        if (key == "rate" || key == "transient" || key == "sample_interval" || key == "checkpoint_steps") return true;
        if (key == "strain") return p.rate > 0.0;
        if (key == "rate_ladder" || key == "ladder_from") return !p.rate_ladder.empty();
        if (key == "frame_interval") return p.frame_interval != 0.0;  // recorded only when set
        if (key == "time") return p.rate == 0.0;
    }
    return contains(m->parameters, key);
}

std::vector<const ParamInfo*> used_parameters(const ReplicaParams& p) {
    std::vector<const ParamInfo*> out;
    for (const auto& info : parameters())
        if (uses_parameter(p, info.key)) out.push_back(&info);
    return out;
}

namespace {
constexpr double kYear = 365.25 * 86400.0;  // s

/// A count or a duration to three significant digits ("2e+301", "1.5e+04").
std::string three_digits(double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.3g", v);
    return buffer;
}

/// None when the periodic box of p.n disks holds twice the neighbour list's range (the large
/// diameter + skin), else the refusal: of N with the least N allowed (below it the list cannot
/// tell a pair from its image, and the replica failed at its first step), or of the larger of
/// skin and size_ratio when no N of fewer than 10^15 disks would do.
std::optional<ParamError> box_holds_the_list(const ReplicaParams& p) {
    if (!(p.phi > 0.0 && p.phi < 1.0 && std::isfinite(p.skin) && p.skin > 0.0 && std::isfinite(p.size_ratio) &&
          p.size_ratio >= 1.0))
        return std::nullopt;  // those parameters' own checks speak first
    const double range = p.size_ratio + p.skin;
    if (box_side_for(p.n, p.phi, p.size_ratio) >= 2.0 * range) return std::nullopt;
    // The side grows as sqrt(N): the smallest N that fits, from N = 2's side, checked upwards.
    const std::int64_t step = p.size_ratio == 1.0 ? 1 : 2;
    const double two = box_side_for(2, p.phi, p.size_ratio);
    const double estimate = std::ceil(2.0 * std::pow(2.0 * range / two, 2.0));
    if (!(estimate < 1e15)) {
        const bool skin = p.skin >= p.size_ratio;
        return ParamError{skin ? "skin" : "size_ratio", show_value(skin ? p.skin : p.size_ratio),
                          std::string(skin ? "a skin" : "a size_ratio") +
                              " that the box of some N holds twice over with " + (skin ? "size_ratio" : "skin") +
                              " (the neighbour range size_ratio + skin = " + show_value(range) +
                              " needs more than 10^15 disks here; a skin of 0.3 to 1 diameters is usual)"};
    }
    auto least = std::max<std::int64_t>(2, static_cast<std::int64_t>(estimate) - 2 * step);
    least += least % step;
    while (box_side_for(least, p.phi, p.size_ratio) < 2.0 * range) least += step;
    char text[400];
    std::snprintf(text, sizeof text,
                  "N >= %lld at phi = %g, size_ratio = %g, skin = %g (the periodic box, side %.3g at this N, must "
                  "span twice the neighbour range size_ratio + skin = %g)",
                  static_cast<long long>(least), p.phi, p.size_ratio, p.skin, box_side_for(p.n, p.phi, p.size_ratio),
                  range);
    return ParamError{"N", show_value(ParamValue{p.n}), text};
}

/// "" when the neighbour list's cell grid can cover the box (at most kMaxCellsPerSide list
/// ranges per side); else the refusal, blamed on phi when a larger phi fits this N, else on
/// N (with the most disks that fit at this phi).
std::optional<ParamError> cell_grid_fits(const ReplicaParams& p) {
    if (!(p.phi > 0.0 && p.phi < 1.0 && std::isfinite(p.skin) && p.skin > 0.0 && std::isfinite(p.size_ratio) &&
          p.size_ratio >= 1.0))
        return std::nullopt;  // those parameters' own checks speak first
    const double range = p.size_ratio + p.skin;
    const double widest = NeighborList::kMaxCellsPerSide * range;
    const double side = box_side_for(p.n, p.phi, p.size_ratio);
    if (side < widest) return std::nullopt;
    // side² = N × mean disk area / phi. The least phi whose box is `widest` wide (from the
    // side at phi = 1, finite where this one is not), and the most disks at this phi.
    const double side_at_one = box_side_for(p.n, 1.0, p.size_ratio);
    const double least_phi = (side_at_one / widest) * (side_at_one / widest) * 1.0000001;
    const std::int64_t step = p.size_ratio == 1.0 ? 1 : 2;
    auto most = static_cast<std::int64_t>(static_cast<double>(p.n) * p.phi / least_phi) + 2 * step;
    most -= most % step;
    while (most > step && box_side_for(most, p.phi, p.size_ratio) >= widest) most -= step;
    char why[300], text[500];
    std::snprintf(why, sizeof why,
                  "size_ratio = %g, skin = %g: the periodic box, side %.3g here, may span at most %d neighbour "
                  "ranges size_ratio + skin = %g, the cell grid of the neighbour list",
                  p.size_ratio, p.skin, side, NeighborList::kMaxCellsPerSide, range);
    if (box_side_for(most, p.phi, p.size_ratio) >= widest) {  // no N at all at this phi
        std::snprintf(text, sizeof text, "phi >= %.3g at N = %lld (%s)", least_phi, static_cast<long long>(p.n), why);
        return ParamError{"phi", show_value(p.phi), text};
    }
    if (least_phi < 1.0) {
        std::snprintf(text, sizeof text, "phi >= %.3g at N = %lld, or N <= %lld at phi = %g (%s)", least_phi,
                      static_cast<long long>(p.n), static_cast<long long>(most), p.phi, why);
        return ParamError{"phi", show_value(p.phi), text};
    }
    std::snprintf(text, sizeof text, "N <= %lld at phi = %g (%s)", static_cast<long long>(most), p.phi, why);
    return ParamError{"N", show_value(ParamValue{p.n}), text};
}

/// Runs of whole steps: a run shorter than one step ran one step past the request (rate =
/// 10: strain 2 for 0.05) or none (rate = 1e308) and was recorded done; a cooling ramp takes
/// between one step and kMostSteps (cooling_time / dt overflowed to 0 steps); a quasistatic
/// strain step no larger than the strain, dividing it (the last step sheared past it), and at
/// most kMostSteps of them (strain_step = 1e-300 overflowed the step count and ran without end).
std::vector<ParamError> run_in_whole_steps(const ReplicaParams& p, const ModelInfo& m) {
    std::vector<ParamError> out;
    if (uses_parameter(p, "dt") && m.kind == ModelKind::Dynamics) {
        const double duration = p.rate > 0.0 ? p.strain / p.rate : p.time;
        if (duration < p.dt)
            out.push_back({"dt", show_value(p.dt),
                           "dt <= " + three_digits(duration) + " here: " +
                               (p.rate > 0.0 ? "strain = " + show_value(p.strain) + " at rate = " + show_value(p.rate) +
                                                   " lasts " + three_digits(duration)
                                             : "time = " + show_value(p.time)) +
                               ", and one step would run past it (check dt, strain (time) and rate)"});
    }
    if (uses_parameter(p, "cooling_time") && uses_parameter(p, "dt")) {
        const double steps = p.cooling_time / p.dt;
        if (!(steps >= 1.0 && steps <= kMostSteps))
            out.push_back({"cooling_time", show_value(p.cooling_time),
                           "cooling_time between dt and " + three_digits(kMostSteps) + " steps of dt = " +
                               show_value(p.dt) + " (it would take " + three_digits(steps) + " steps)"});
    }
    if (uses_parameter(p, "strain_step") && uses_parameter(p, "strain")) {
        const double steps = p.strain / p.strain_step;
        if (p.strain_step > p.strain)
            out.push_back({"strain_step", show_value(p.strain_step),
                           "strain_step <= strain = " + show_value(p.strain) + " (a larger step shears past the run)"});
        else if (!(steps <= kMostSteps))  // each step is a minimisation; counted in 64 bits
            out.push_back({"strain_step", show_value(p.strain_step),
                           "strain_step >= strain / " + three_digits(kMostSteps) + " = " +
                               three_digits(p.strain / kMostSteps) + " (strain = " + show_value(p.strain) +
                               " would take " + three_digits(steps) + " minimisations)"});
        else if (std::abs(steps - std::round(steps)) > 1e-9 * steps)  // the last step sheared past it
            out.push_back({"strain_step", show_value(p.strain_step),
                           "strain_step dividing strain = " + show_value(p.strain) + " into whole steps (" +
                               show_value(p.strain) + " / " + show_value(p.strain_step) + " = " + three_digits(steps) +
                               " steps: the last would shear to " +
                               three_digits(static_cast<double>(shear_steps(p.strain, p.strain_step)) * p.strain_step) +
                               ")"});
    }
    return out;
}

/// The thermal models' Euler–Maruyama kick, sqrt(2 T dt / kd) per component, must stay within
/// a small diameter d_s, or a step jumps disks through each other instead of resolving their
/// contacts (temperature = 1e308 ran to non-finite positions, blamed on dt). The models use
/// T <= 1e-2 k_e; the bound, T <= kd d_s^2 / (2 dt), is 2.5 k_e at dt = 0.2, kd = 1.
std::optional<ParamError> thermal_kick_resolved(const ReplicaParams& p) {
    if (!uses_parameter(p, "temperature") || !uses_parameter(p, "dt") || !uses_parameter(p, "kd")) return std::nullopt;
    const double most = p.kd / (2.0 * p.dt);  // d_s = 1
    if (p.temperature <= most) return std::nullopt;
    return ParamError{"temperature", show_value(p.temperature),
                      "temperature <= kd / (2 dt) = " + three_digits(most) + " here: a step of dt = " +
                          show_value(p.dt) + " would kick a disk by sqrt(2 temperature dt / kd) = " +
                          three_digits(std::sqrt(2.0 * p.temperature * p.dt / p.kd)) +
                          " small diameters, and the steps must resolve contacts (at most 1)"};
}

/// Samples and frames come at whole steps: an interval below one step was raised to one step
/// while the archive recorded the value asked for (1e-6 sampled every 0.002); and a transient
/// after the last sample left nothing to average (NaN means, an all-NaN g_y). For a valid p.
std::vector<ParamError> sampling_in_steps(const ReplicaParams& p, const ModelInfo& m) {
    std::vector<ParamError> out;
    const RunLength run = run_length(p);
    if (!run.key || !uses_parameter(p, "sample_interval")) return out;
    const Schedule s = m.schedule(p);
    if (s.steps <= 0) return out;
    const double per_step = run.value / static_cast<double>(s.steps);  // strain (time) of one step
    const std::string step_is = std::string("one step (") + run.key + " " + three_digits(per_step) + " here)";
    // At rate 0 the intervals are times, and the default sample_interval (0.01, a strain) is
    // below a step of dt: a sample every step, as documented; only strains are checked.
    const bool in_strain = std::string_view(run.key) == "strain";
    const auto below_a_step = [&](double interval) { return in_strain && interval < per_step * (1.0 - 1e-9); };
    if (below_a_step(p.sample_interval))
        out.push_back({"sample_interval", show_value(p.sample_interval),
                       "sample_interval >= " + step_is + ": samples come at whole steps"});
    if (uses_parameter(p, "frame_interval") && p.frame_interval > 0.0 && below_a_step(p.frame_interval))
        out.push_back({"frame_interval", show_value(p.frame_interval),
                       "frame_interval >= " + step_is + ", or 0 for none: frames come at whole steps"});
    if (uses_parameter(p, "transient") && out.empty())
        if (const SamplesAfterTransient after = samples_after_transient(p, s, run); after.count == 0)
            out.push_back({"transient", show_value(p.transient),
                           "transient <= " + three_digits(after.last) + " here, the last sample's " + run.key +
                               " (sample_interval = " + show_value(p.sample_interval) +
                               "): no sample after the transient leaves the averages and g_y empty"});
    return out;
}

}  // namespace

std::vector<ParamError> validate(const ReplicaParams& p) {
    const ModelInfo* m = find_model(p.model);
    if (!m) return {{"model", show_in_message(p.model), "one of: " + model_list()}};
    std::vector<ParamError> errors;
    for (const ParamInfo* info : used_parameters(p))
        if (info->check)
            if (std::string allowed = info->check(p); !allowed.empty()) {
                // inf fails "rate >= 0" by being infinite, which the bound alone does not say.
                const ParamValue value = get_value(p, *info);
                if (const double* number = std::get_if<double>(&value); number && !std::isfinite(*number))
                    allowed = "a finite number, " + allowed;
                errors.push_back({std::string(info->key), show_in_message(value), allowed});
            }
    if (!errors.empty()) return errors;
    if (auto too_small = box_holds_the_list(p)) errors.push_back(*too_small);
    if (auto too_wide = cell_grid_fits(p)) errors.push_back(*too_wide);
    for (ParamError& e : run_in_whole_steps(p, *m)) errors.push_back(std::move(e));
    if (uses_parameter(p, "dt") && p.dt > m->stable_dt(p))
        errors.push_back({"dt", show_value(p.dt),
                          "dt <= " + show_value(m->stable_dt(p)) + " " +
                              (m->stable_dt_basis ? m->stable_dt_basis(p)
                                                  : "for " + p.model + " with mass " + show_value(p.mass) + " and kd " +
                                                        show_value(p.kd) + " (stability of the integrator)")});
    if (auto kick = thermal_kick_resolved(p)) errors.push_back(*kick);  // after dt's own limit
    // The transient and the sampling against the run length (strain, or time at rate 0): a
    // transient that covers the run leaves nothing to average (empty means, an all-NaN g_y),
    // a sample interval beyond it only the first sample.
    if (const RunLength run = run_length(p); run.key) {
        if (uses_parameter(p, "transient") && p.transient >= run.value)
            errors.push_back({"transient", show_value(p.transient),
                              std::string("transient < ") + run.key + " = " + show_value(run.value) +
                                  " (averages and g_y use the samples after the transient)"});
        // Steps are counted in 64 bits, and far fewer than that fit any allocation.
        if (uses_parameter(p, "dt") && m->kind == ModelKind::Dynamics) {
            const double duration = p.rate > 0.0 ? p.strain / p.rate : p.time;
            const double largest_dt = m->stable_dt(p);
            // A rate so small that no stable dt fits the run (1e-320 said "dt >= inf").
            if (p.rate > 0.0 && !(duration / largest_dt <= kMostSteps))
                errors.push_back({"rate", show_value(p.rate),
                                  "rate >= " + three_digits(p.strain / (kMostSteps * largest_dt)) + " here: strain = " +
                                      show_value(p.strain) + " would take " + three_digits(duration / largest_dt) +
                                      " steps even at the largest stable dt = " + three_digits(largest_dt) +
                                      ", and a replica runs at most " + three_digits(kMostSteps) +
                                      " (check strain and rate)"});
            else if (!(duration / p.dt <= kMostSteps))
                errors.push_back({"dt", show_value(p.dt),
                                  "dt >= " + three_digits(duration / kMostSteps) + " here: " + run.key + " = " +
                                      show_value(run.value) + (p.rate > 0.0 ? " at rate = " + show_value(p.rate) : "") +
                                      " would take " + three_digits(duration / p.dt) +
                                      " steps, and a replica runs at most " + three_digits(kMostSteps) +
                                      " (check dt, " + run.key + " and rate)"});
        }
        if (uses_parameter(p, "sample_interval") && p.sample_interval > run.value)
            errors.push_back({"sample_interval", show_value(p.sample_interval),
                              std::string("sample_interval <= ") + run.key + " = " + show_value(run.value) +
                                  " (a longer interval samples only the initial state)"});
        if (uses_parameter(p, "frame_interval") && p.frame_interval > run.value)
            errors.push_back({"frame_interval", show_value(p.frame_interval),
                              std::string("frame_interval <= ") + run.key + " = " + show_value(run.value) +
                                  ", or 0 for none (a longer interval keeps only the initial state)"});
    }
    if (errors.empty())
        for (ParamError& e : sampling_in_steps(p, *m)) errors.push_back(std::move(e));
    return errors;
}

std::vector<std::pair<std::string, std::string>> advisories(const ReplicaParams& p) {
    std::vector<std::pair<std::string, std::string>> out;
    const ModelInfo* m = find_model(p.model);
    if (!m || !validate(p).empty()) return out;
    if (m->advisory)
        if (std::string note = m->advisory(p); !note.empty()) out.emplace_back("dt", note);
    // A replica that no allocation can finish is almost always a typo (dt, strain, rate).
    if (const double seconds = m->cost(p) / kNominalEvaluationsPerSecond; seconds > kYear)
        out.emplace_back("cost", "a replica of N = " + std::to_string(p.n) + " at rate = " + show_value(p.rate) +
                                     " would take about " + three_digits(seconds / kYear) +
                                     " core-years at the nominal speed (" + std::to_string(m->schedule(p).steps) +
                                     " steps): check dt, strain (time) and rate; jamsim run --dry-run measures it");
    // Below alpha = 1.5 the contact stiffness k (1 - r/d)^(alpha - 2) grows without bound as an
    // overlap closes; CG and FIRE then crawl (jamsim minimize --N 64 --phi 0.85: alpha = 2 in
    // 701 CG iterations, 1.5 in 3005, 1.3 in 7794 or not in 2e5 by seed, 1.2 not in 2e5).
    if (uses_parameter(p, "minimizer") && p.alpha < kSlowMinimizationAlpha)
        out.emplace_back("alpha", "alpha = " + show_value(p.alpha) + " is below " + show_value(kSlowMinimizationAlpha) +
                                      ": the contact stiffness (1 - r/d)^(alpha - 2) diverges at contact, and "
                                      "energy minimisations may run to their iteration limit without converging "
                                      "(at N = 64: alpha = 1.3 needed 8e3 to more than 2e5 CG iterations, "
                                      "alpha = 2 needs about 700)");
    // Samples at or after the transient, from the schedule (both ends are sampled).
    const RunLength run = run_length(p);
    if (run.key && uses_parameter(p, "transient") && uses_parameter(p, "sample_interval")) {
        const std::int64_t after = samples_after_transient(p, m->schedule(p), run).count;
        if (after < kFewSamples)
            out.emplace_back("samples", "transient = " + show_value(p.transient) + " leaves " + std::to_string(after) +
                                            " samples (" + run.key + " = " + show_value(run.value) +
                                            ", sample_interval = " + show_value(p.sample_interval) +
                                            ") for the averages and g_y, fewer than " + std::to_string(kFewSamples) +
                                            ": they will be noisy");
    }
    return out;
}

Schedule schedule_of(const ReplicaParams& p) { return model_of(p).schedule(p); }
std::int64_t checkpointed_steps(const ReplicaParams& p) {
    const ModelInfo& m = model_of(p);
    return m.checkpointed_steps ? m.checkpointed_steps(p) : m.schedule(p).steps;
}
double estimated_cost(const ReplicaParams& p) { return model_of(p).cost(p); }
int evaluations_per_step(const ReplicaParams& p) { return model_of(p).evaluations_per_step(p); }

double estimated_memory(const ReplicaParams& p) {
    const double row_bytes = 8.0 * static_cast<double>(std::size(kSampleColumns));
    const double grid =
        p.phi > 0.0 ? NeighborList::cell_grid_bytes(box_side_for(p.n, p.phi, p.size_ratio), p.size_ratio + p.skin)
                    : 0.0;
    return static_cast<double>(p.n) * model_of(p).bytes_per_disk +
           3.0 * row_bytes * static_cast<double>(sample_count(p)) + grid;
}

std::int64_t sample_count(const ReplicaParams& p) {
    const Schedule s = schedule_of(p);
    return s.steps / s.sample_every + 1;
}

std::int64_t frame_count(const ReplicaParams& p) {
    const Schedule s = schedule_of(p);
    return s.frame_every > 0 ? s.steps / s.frame_every + 1 : 0;
}

namespace {
std::string describe_parameters(const ReplicaParams& p, bool run_length) {
    std::string out;
    run_length = run_length || !model_of(p).extendable;
    for (const ParamInfo* info : used_parameters(p)) {
        if (!run_length && (info->key == "strain" || info->key == "time")) continue;
        if (!out.empty()) out.push_back(' ');
        out.append(info->key).append("=").append(show_value(get_value(p, *info)));
    }
    return out;
}
}  // namespace

std::string describe(const ReplicaParams& p) { return describe_parameters(p, true); }
std::string describe_without_run_length(const ReplicaParams& p) { return describe_parameters(p, false); }

std::uint64_t replica_identity(const ReplicaParams& p) {
    std::string text = "jamsim replica";
    for (const ParamInfo* info : used_parameters(p))
        if (info->identity == Identity::Physics && info->key != "seed")
            text.append(" ").append(info->key).append("=").append(show_value(get_value(p, *info)));
    return hash64(text);
}

RandomKey random_key(const ReplicaParams& p) { return {p.seed, replica_identity(p)}; }

}  // namespace jamsim

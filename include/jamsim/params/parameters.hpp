#pragma once
// Every input of a replica, described once. The campaign reader, validation, the campaign
// fingerprint, the archive's parameter columns, the replica file's attributes, the command
// line of `jamsim replica` and the parameter table of campaigns/README.md are all produced
// from kParameters below; adding a parameter is a field of ReplicaParams plus one row there.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace jamsim {

/// Everything that defines one replica; its output depends on nothing else. Units: k_e =
/// k_d = d_s = 1 unless a parameter changes them, τ = k_d d_s²/k_e. Defaults are those of
/// kParameters (the single source; campaigns/README.md's table is printed from it).
struct ReplicaParams {
    std::string model = "RD0";                 ///< a registered model or protocol (run/model_registry.hpp)
    std::int64_t n = 1024;                     ///< number of disks N
    double phi = 0.84;                         ///< packing fraction Σ π d_i² / (4 L²)
    double rate = 1e-4;                        ///< shear rate γ̇, 1/τ
    std::uint64_t seed = 1;                    ///< random seed (with the replica's identity, the RNG key)
    double strain = 2.0;                       ///< total strain (rate > 0; QS, SHEARED)
    double time = 0.0;                         ///< total time at rate 0, τ
    double transient = 0.0;                    ///< strain (time at rate 0) excluded from averages
    double sample_interval = 0.01;             ///< strain (time at rate 0) between samples
    double frame_interval = 0.0;               ///< strain (time at rate 0) between configuration frames; 0: none
    std::int64_t checkpoint_steps = 10000;     ///< steps between checkpoint steps (run/replica.hpp)
    std::string rate_ladder = "";              ///< "down": each (N, phi, seed) runs its rates high to low
    double ladder_from = 0.0;                  ///< rate of the replica whose end state starts this one (derived)
    std::string initial = "";                  ///< archive whose final states start the replicas ("": random)
    std::string initial_match = "parameters";  ///< "parameters" (N, phi, seed) or "id"
    double dt = 0.2;                           ///< time step Δt, τ
    std::string integrator = "euler";          ///< overdamped models: "euler" or "heun"
    double kd = 1.0;                           ///< dissipation coefficient k_d
    double mass = 1.0;                         ///< massive models: mass of a small disk
    double delta = 1e-3;                       ///< CD0: substrate drag δ = k_0/k_d
    std::string solver = "auto";               ///< CD0 backend: "auto", "petsc" or "eigen"
    std::string petsc_options = "";            ///< CD0: extra PETSc options (prefix cd0_)
    double temperature = 1e-3;                 ///< thermal models: temperature T (COOL: T₀), k_e
    double cooling_time = 1e4;                 ///< COOL: time over which T falls linearly to 0, τ
    std::string minimizer = "cg";              ///< minimisation: "cg", "cg-pr" or "fire"
    double strain_step = 1e-4;                 ///< QS, SHEARED: strain between minimisations
    double energy_floor = 1e-16;               ///< E/N below this after minimisation: unjammed, k_e
    double force_tol = 1e-10;                  ///< force balance relative to the mean contact force
    double force_tol_abs = 1e-14;              ///< force balance floor, k_e/d_s
    double phi_tol = 1e-6;                     ///< φ_J searches: width of the final bracket
    double alpha = 2.0;                        ///< potential exponent α (2 harmonic, 2.5 Hertzian)
    double size_ratio = 1.4;                   ///< large/small diameter (1 = monodisperse)
    double skin = 0.3;                         ///< neighbour-list skin, d_s
};

/// A parameter value as read from a file or a command line, or stored.
using ParamValue = std::variant<double, std::int64_t, std::string>;

/// Where a parameter lives in ReplicaParams.
using ParamField = std::variant<double ReplicaParams::*, std::int64_t ReplicaParams::*, std::uint64_t ReplicaParams::*,
                                std::string ReplicaParams::*>;

/// What a parameter contributes to a replica's random key (see replica_identity).
enum class Identity : std::uint8_t {
    Physics,   ///< part of the key: a different value is a different replica
    Numerics,  ///< not part of the key: run length, sampling, time step, solver settings;
               ///< the same physical replica run longer or more finely starts the same way
};

/// One row of the parameter table.
struct ParamInfo {
    std::string_view key;          ///< snake_case: campaign key, archive column, file attribute
    std::string_view table;        ///< TOML table ("model", "potential", "system", "run", "sweep");
                                   ///< "" for a parameter derived from the others, not an input
    std::string_view toml_key;     ///< key inside that table (usually == key; "name", "seeds")
    std::string_view flag;         ///< `jamsim replica` option ("--sample-interval")
    std::string_view units;        ///< "1" when dimensionless
    std::string_view description;  ///< one line, for --help, the README and archive attributes
    ParamField field;
    Identity identity;
    /// "" when `p` has a usable value, else what is allowed ("0 < phi < 1"); may look at
    /// other parameters (N even unless size_ratio = 1). Model-specific limits (a stable Δt)
    /// come from the model's registration.
    std::string (*check)(const ReplicaParams& p);
    std::string_view allowed;  ///< the allowed values, for tables and --help
};

/// Every parameter, in the order of files, columns and tables.
std::span<const ParamInfo> parameters();
/// The row of `key`, or nullptr.
const ParamInfo* find_parameter(std::string_view key);

ParamValue get_value(const ReplicaParams& p, const ParamInfo& info);
/// Sets a value of the field's kind (an integer is accepted for a real); returns false when
/// the value has the wrong kind (a text for a number, a fraction for an integer).
bool set_value(ReplicaParams& p, const ParamInfo& info, const ParamValue& value);
/// The value as a person writes it ("0.84", "RD0"), round-tripping doubles (17 digits).
std::string show_value(const ParamValue& value);
/// show_value for a message: a text that is empty or starts or ends with white space in
/// double quotes ("RD0 " read as RD0), everything else as show_value.
std::string show_in_message(const ParamValue& value);
/// The default of a parameter (ReplicaParams{}), as text.
std::string default_text(const ParamInfo& info);
/// Parse text (a command-line argument) into the field's kind; false when it does not parse.
bool parse_value(const ParamInfo& info, const std::string& text, ParamValue& out);
/// True for numeric fields (stored as float64 columns); text fields are campaign-wide
/// attributes.
bool is_numeric(const ParamInfo& info);
/// What a value of the field's kind is, for messages: "a number", "an integer", "a whole
/// number from 0 to 9223372036854775807" (seeds) or "a string".
std::string value_kind(const ParamInfo& info);
double numeric_value(const ReplicaParams& p, const ParamInfo& info);

/// A problem with one parameter, phrased for a person.
struct ParamError {
    std::string key;      ///< the table's key
    std::string value;    ///< the offending value
    std::string allowed;  ///< what is allowed
};

}  // namespace jamsim

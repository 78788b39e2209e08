#pragma once
#include <limits>
#include <string>
#include <vector>

namespace jamsim {

/// One row of observables, sampled at the start of a step (the state whose forces were just
/// computed). Definitions (units: k_e = k_d = d_s = 1, τ = k_d d_s²/k_e, A = L²):
struct Sample {
    double time;                         ///< t = n Δt, τ
    double strain;                       ///< accumulated strain γ̇ t (not wrapped), 1
    double energy_per_particle;          ///< E/N = (1/N) Σ_pairs V(r_ij), k_e
    double pressure;                     ///< p = (1/2A) Σ_pairs r_ij · f_ij, k_e/d_s²
    double shear_stress;                 ///< σ = −(1/A) Σ_pairs r_ij,x f_ij,y, k_e/d_s²
    double contact_number;               ///< z = 2 N_c / N, contacts per particle (rattlers included)
    double nonaffine_velocity_sq;        ///< (1/N) Σ |u_i|², u = v − γ̇ y x̂, (d_s/τ)²
    double pressure_dissipative;         ///< p of the dissipative contact forces, k_e/d_s²
    double shear_stress_dissipative;     ///< −(1/A) Σ r_ij,y f^dis_ij,x, k_e/d_s²
    double input_power;                  ///< (σ + σ_dis + σ_kin) γ̇ A / N: work of the shear, k_e/τ per disk
    double dissipated_power;             ///< dissipated power / N, k_e/τ per disk
    double kinetic_energy_per_particle;  ///< ½ Σ m|u|² / N (co-moving frame), k_e
    double pressure_kinetic;             ///< (1/2A) Σ m |u|², k_e/d_s²
    double shear_stress_kinetic;         ///< −(1/A) Σ m u_x u_y, k_e/d_s²
    double solver_iterations;            ///< CD0: Krylov iterations per solve; QS and static
                                         ///< protocols: minimiser iterations (diagnostic)
    // Static states (QS, RAND, COMPRESS); NaN where they do not apply.
    static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    double packing_fraction = kNone;           ///< φ of the sampled state
    double contact_number_nonrattler = kNone;  ///< Z = 2 N_c′ / N′ after rattler removal
    double rattler_fraction = kNone;           ///< 1 − N′/N
    double excess_contacts = kNone;            ///< N_c′ − (2(N′ − 1) + 1): 0 at isostaticity
    double jammed = kNone;                     ///< 1: E/N ≥ energy floor after minimisation, 0: not
    double max_force = kNone;                  ///< largest force component after minimisation
};

/// A named column of a time series, as written to the archive.
struct ColumnInfo {
    const char* name;
    const char* units;
    const char* description;
    double Sample::*member;
};

/// Schema of Sample: the writer creates one dataset per entry, so adding an observable is a
/// Sample field plus a line here.
inline constexpr ColumnInfo kSampleColumns[] = {
    {"time", "tau", "t = n dt, tau = k_d d_s^2 / k_e", &Sample::time},
    {"strain", "1", "accumulated strain rate * t (not wrapped)", &Sample::strain},
    {"energy_per_particle", "k_e", "E/N = (1/N) sum_pairs V(r_ij)", &Sample::energy_per_particle},
    {"pressure", "k_e/d_s^2", "p = (1/2A) sum_pairs r_ij . f_ij", &Sample::pressure},
    {"shear_stress", "k_e/d_s^2", "sigma = -(1/A) sum_pairs r_ij,x f_ij,y", &Sample::shear_stress},
    {"contact_number", "1", "z = 2 N_contacts / N (rattlers included)", &Sample::contact_number},
    {"nonaffine_velocity_sq", "d_s^2/tau^2", "(1/N) sum_i |v_i - rate y_i x|^2", &Sample::nonaffine_velocity_sq},
    {"pressure_dissipative", "k_e/d_s^2", "pressure of the dissipative contact forces (CD0)",
     &Sample::pressure_dissipative},
    {"shear_stress_dissipative", "k_e/d_s^2", "-(1/A) sum_contacts r_ij,y f^dis_ij,x (CD0; 0 for reservoir drag)",
     &Sample::shear_stress_dissipative},
    {"input_power", "k_e/tau", "(shear_stress + shear_stress_dissipative + shear_stress_kinetic) rate A / N",
     &Sample::input_power},
    {"dissipated_power", "k_e/tau", "dissipated power per disk (RD0: k_d |u|^2 averaged)", &Sample::dissipated_power},
    {"kinetic_energy_per_particle", "k_e", "(1/N) sum m_i |u_i|^2 / 2, co-moving frame (massive models)",
     &Sample::kinetic_energy_per_particle},
    {"pressure_kinetic", "k_e/d_s^2", "(1/2A) sum m_i |u_i|^2", &Sample::pressure_kinetic},
    {"shear_stress_kinetic", "k_e/d_s^2", "-(1/A) sum m_i u_ix u_iy", &Sample::shear_stress_kinetic},
    {"solver_iterations", "1",
     "CD0: Krylov iterations per contact solve at this sample (0: direct or none); QS and static protocols: minimiser "
     "iterations",
     &Sample::solver_iterations},
    {"packing_fraction", "1", "phi of the sampled state", &Sample::packing_fraction},
    {"contact_number_nonrattler", "1",
     "Z = 2 N_c' / N' after iterative removal of disks with < 3 contacts (static states)",
     &Sample::contact_number_nonrattler},
    {"rattler_fraction", "1", "1 - N'/N (static states)", &Sample::rattler_fraction},
    {"excess_contacts", "1", "N_c' - (2(N' - 1) + 1), 0 at isostaticity (static states)", &Sample::excess_contacts},
    {"jammed", "1", "1 if E/N >= energy_floor after minimisation, else 0 (static states)", &Sample::jammed},
    {"max_force", "k_e/d_s", "largest force component after minimisation (static states)", &Sample::max_force},
};

/// Rows of samples, stored by column.
class TimeSeries {
  public:
    void push(const Sample& s) { rows_.push_back(s); }
    std::size_t size() const { return rows_.size(); }
    const Sample& operator[](std::size_t k) const { return rows_[k]; }
    /// One column as a contiguous array.
    std::vector<double> column(double Sample::*member) const {
        std::vector<double> out;
        out.reserve(rows_.size());
        for (const auto& r : rows_) out.push_back(r.*member);
        return out;
    }

  private:
    std::vector<Sample> rows_;
};

/// Mean of a column over the rows with strain ≥ from_strain (NaN when there are none).
double mean_after(const TimeSeries& ts, double Sample::*member, double from_strain, bool in_time = false);

}  // namespace jamsim

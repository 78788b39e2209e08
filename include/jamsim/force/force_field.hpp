#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"
#include "jamsim/potential/soft_sphere.hpp"

namespace jamsim {

/// The elastic interaction of a replica: pair evaluator + neighbour list + rebuild policy.
/// Models ask it for forces; they never touch the list themselves.
class ForceField {
  public:
    ForceField(potential::SoftSphere pot, double skin) : pot_(pot), list_(skin) {}

    /// Forces on the system's particles (into particles.fx, fy) at a step boundary. When the
    /// list is stale the particles are wrapped into the cell, sorted by cell for memory
    /// locality, and the list is rebuilt.
    ForceResult compute(System& sys, Tally tally = Tally::Full);

    /// Forces for trial positions inside a step (e.g. a Heun predictor) at the box's current
    /// strain; rebuilds the list from the trial positions if needed but reorders nothing.
    ForceResult compute_at(const Box& box, std::span<const double> x, std::span<const double> y,
                           std::span<const double> diameter, std::span<double> fx, std::span<double> fy,
                           Tally tally = Tally::ForcesOnly);

    /// Forces for positions split as base + offset (a minimiser's coordinates): the list is
    /// kept valid for the total positions (x_total = base + offset, which the caller keeps
    /// current), separations are formed as (base difference) + (offset difference).
    /// displacement_bound ≥ 0: a bound on every disk's lab displacement since the list's last
    /// build (see builds()), which lets the per-disk rebuild check be skipped.
    ForceResult compute_split(const Box& box, std::span<const double> x_total, std::span<const double> y_total,
                              std::span<const double> base_x, std::span<const double> base_y,
                              std::span<const double> off_x, std::span<const double> off_y,
                              std::span<const double> diameter, std::span<double> fx, std::span<double> fy, Tally tally,
                              double displacement_bound = -1.0);

    /// Forget the list (after a Lees–Edwards wrap remapped the positions).
    void invalidate() {
        list_.invalidate();
        recorded_ = false;
    }

    /// From the next evaluation on, compute() and compute_at() also record which list
    /// entries touch and each disk's Σ r_y over its contacts (ContactRecord): CD0 reads them
    /// instead of walking the pairs again.
    void record_contacts() { recording_ = true; }

    /// The contacts recorded by the last evaluation, when it recorded them and was at these
    /// very positions (the same arrays, at the box's current strain); else null.
    /// touching: shape [list().size()], sum_ry: shape [N].
    struct RecordedContacts {
        std::span<const std::uint8_t> touching;
        std::span<const double> sum_ry;
    };
    std::optional<RecordedContacts> recorded_contacts(const Box& box, std::span<const double> x,
                                                      std::span<const double> y) const;

    const NeighborList& list() const { return list_; }
    std::size_t builds() const { return list_.builds(); }
    const potential::SoftSphere& potential() const { return pot_; }

  private:
    /// The record's storage for an evaluation at (x, y), or {} when not recording.
    ContactRecord start_record(const Box& box, std::span<const double> x, std::span<const double> y);

    potential::SoftSphere pot_;
    NeighborList list_;
    PairScratch scratch_;
    bool recording_ = false;
    bool recorded_ = false;  // the last evaluation recorded, at the positions below
    const double* recorded_x_ = nullptr;
    const double* recorded_y_ = nullptr;
    double recorded_strain_ = 0.0;
    std::size_t recorded_builds_ = 0;  // the list's build the record indexes
    std::vector<std::uint8_t> touching_;
    std::vector<double> sum_ry_;
};

/// Move sheared positions with a lab-frame non-affine velocity field (v_x, v_y) at strain γ
/// for a time `scale`: x += scale (v_x − γ v_y), y += scale v_y (thesis eq. 4.5).
void drift(std::span<double> x, std::span<double> y, std::span<const double> vx, std::span<const double> vy,
           double gamma, double scale);

/// Set γ to `strain` (it may leave [−1/2, 1/2) by at most one step's worth), then wrap it
/// back and remap the positions if it crossed ±1/2, invalidating the neighbour list.
void apply_strain(System& sys, ForceField& forces, double strain);

}  // namespace jamsim

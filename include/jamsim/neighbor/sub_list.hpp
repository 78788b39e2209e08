#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "jamsim/core/box.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"

namespace jamsim {

/// The pairs of a NeighborList that lie within a smaller skin: a Verlet list of its own,
/// filtered from the parent's pairs instead of built through cells, with the parent's entry
/// layout (owner, neighbour, image shift, contact distance).
///
/// It lists every pair that can touch while the parent is valid and no disk has moved, in
/// the sheared frame since the sub-list's build, further than the parent's argument allows
/// for this skin: 2 max_i |M(γ)δs_i| + |Δγ|(d_max + skin) ≤ skin (NeighborList). Why: the CD0
/// contact matrix is factorised on the pattern of its candidate pairs, and a thinner pattern
/// has thinner separators, so less fill and shorter update paths than the force list's.
class SubList {
  public:
    explicit SubList(double skin) : skin_(skin) {}

    double skin() const { return skin_; }

    /// Brings the list up to date for these (sheared, unwrapped since the parent's build)
    /// positions at the box's strain: filtered afresh from `parent` when the parent was built
    /// since, or when a pair left out may touch. Returns whether it was.
    bool update(const NeighborList& parent, const Box& box, std::span<const double> x, std::span<const double> y);

    /// Number of filterings so far (a new value means new pairs).
    std::size_t builds() const { return builds_; }
    std::size_t size() const { return neighbor_.size(); }
    std::span<const std::int32_t> owner() const { return owner_; }
    std::span<const std::int32_t> neighbor() const { return neighbor_; }
    std::span<const double> contact() const { return contact_; }
    std::span<const double> shift_x() const { return shift_x_; }
    std::span<const double> shift_y() const { return shift_y_; }
    /// Entry k's position in the parent list (at the parent build this list was filtered
    /// from): what the parent's per-entry results (ForceField::recorded_contacts) say of it.
    std::span<const std::uint32_t> parent_entry() const { return parent_entry_; }
    /// The parent build this list was filtered from (NeighborList::builds()).
    std::size_t parent_builds() const { return parent_builds_; }

  private:
    double skin_;
    std::size_t builds_ = 0;
    std::size_t parent_builds_ = static_cast<std::size_t>(-1);
    double max_contact_ = 0.0;
    std::vector<std::int32_t> owner_, neighbor_;
    std::vector<std::uint32_t> parent_entry_;
    std::vector<double> shift_x_, shift_y_, contact_;
    std::vector<double> x_ref_, y_ref_;
    double strain_ref_ = 0.0;
};

}  // namespace jamsim

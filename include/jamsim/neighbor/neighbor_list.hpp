#pragma once
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "jamsim/core/box.hpp"
#include "jamsim/core/particles.hpp"
#include "jamsim/neighbor/force_blocks.hpp"

namespace jamsim {

/// Verlet (half) neighbour list with a skin, built through a cell list in sheared
/// coordinates, valid at any Lees–Edwards strain.
///
/// Pair (i, j) is listed once (i owns it) when its lab distance at build time is below
/// d_ij + skin. Each entry stores the sheared image shift (sx, sy) that makes
/// (x_i − x_j + sx, y_i − y_j + sy) the separation of the nearby image, so the force loop
/// never rounds; positions need not be wrapped between builds.
///
/// Validity (why the rebuild test is safe): between builds a pair's lab separation changes
/// by at most |M(γ)δs_i| + |M(γ)δs_j| + |Δγ| |s_y|, with δs the sheared displacement since
/// the build, M(γ) = [[1, γ], [0, 1]] and |s_y| < d_max + skin for any pair that can
/// touch. So no contact is missed while 2 max_i |M(γ)δs_i| + |Δγ|(d_max + skin) ≤ skin.
class NeighborList {
  public:
    /// Cells per side of the build's grid at most: cell indices (nc² of them) are 32-bit. A
    /// box wider than that many list ranges (a dilute system, φ ≈ 1e-9 at N = 64) is refused
    /// by the parameter checks first; the grid's memory (8 bytes a cell while it is built)
    /// counts in the memory check.
    static constexpr int kMaxCellsPerSide = 46340;
    /// Bytes of the cell grid for this box and list range (`reach` = largest diameter + skin).
    static double cell_grid_bytes(double side, double reach);

    explicit NeighborList(double skin = 0.3) : skin_(skin) {}

    double skin() const { return skin_; }

    /// Build from (possibly unwrapped) sheared positions at the box's current strain.
    void build(std::span<const double> x, std::span<const double> y, std::span<const double> diameter, const Box& box);

    /// Cheap pre-check for callers that know a bound on every disk's lab-frame displacement
    /// since the last build: false means the list is certainly still valid.
    bool may_need_rebuild(double displacement_bound, const Box& box) const {
        if (!valid_) return true;
        const double affine = std::abs(box.strain() - strain_ref_) * (max_diameter_ + skin_);
        return 2.0 * displacement_bound + affine > skin_;
    }

    /// True when the list may miss a contact for these positions and this strain.
    bool needs_rebuild(std::span<const double> x, std::span<const double> y, const Box& box) const;

    /// Force a rebuild at the next check (after a Lees–Edwards wrap or a reorder).
    void invalidate() { valid_ = false; }

    std::size_t size() const { return neighbor_.size(); }
    std::size_t builds() const { return builds_; }

    // CSR layout: entries first_[i] .. first_[i+1]-1 belong to particle i.
    std::span<const std::int32_t> first() const { return first_; }
    std::span<const std::int32_t> neighbor() const { return neighbor_; }
    /// Owner i of each entry (the same information as first(), flat for the force loop).
    std::span<const std::int32_t> owner() const { return owner_; }
    /// Contact distance d_ij = (d_i + d_j)/2 of each entry.
    std::span<const double> contact() const { return contact_; }
    std::span<const double> shift_x() const { return shift_x_; }
    std::span<const double> shift_y() const { return shift_y_; }

    /// The list's fixed decomposition into blocks of disks for the force loop (made with
    /// every build; neighbor/force_blocks.hpp).
    const ForceBlocks& blocks() const { return blocks_; }

  private:
    void build_all_pairs(std::span<const double> x, std::span<const double> y, std::span<const double> diameter,
                         const Box& box);
    void build_with_cells(std::span<const double> x, std::span<const double> y, std::span<const double> diameter,
                          const Box& box, int cells);
    void finish_build(std::span<const double> diameter);
    void remember_reference(std::span<const double> x, std::span<const double> y, const Box& box, double max_d);

    double skin_;
    double max_diameter_ = 0.0;
    bool valid_ = false;
    std::size_t builds_ = 0;
    std::vector<std::int32_t> first_, neighbor_, owner_;
    std::vector<double> shift_x_, shift_y_, contact_;
    ForceBlocks blocks_;
    std::vector<double> x_ref_, y_ref_;
    double strain_ref_ = 0.0;
};

/// The Verlet rule of a list with `skin` built at sheared positions (x_ref, y_ref) and strain
/// `strain_ref`: true when a pair left out may touch at (x, y) and `strain`, i.e. when
/// 2 max_i |M(γ)δs_i| + |Δγ| reach > skin, `reach` bounding |s_y| of any pair that can touch
/// (d_max + skin; see NeighborList).
bool verlet_rule_broken(std::span<const double> x, std::span<const double> y, std::span<const double> x_ref,
                        std::span<const double> y_ref, double strain, double strain_ref, double reach, double skin);

/// Order that sorts particles by their cell in sheared coordinates (cells of side ≥ cell);
/// apply with Particles::permute to keep neighbours close in memory.
std::vector<std::int32_t> spatial_order(const Particles& p, const Box& box, double cell);

}  // namespace jamsim

#include "jamsim/neighbor/neighbor_list.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

namespace {

/// Above any cell index (2^31): a scaled coordinate at or beyond it cannot be converted.
constexpr double kNoCell = 2147483648.0;

/// Particles binned into an nc × nc grid over the primary cell (sheared coordinates).
struct CellGrid {
    int cells = 0;
    std::vector<std::int32_t> start;       // shape [nc*nc + 1]
    std::vector<std::int32_t> members;     // particle indices, grouped by cell, ascending
    std::vector<std::int32_t> cell_of;     // shape [N]
    std::vector<double> image_x, image_y;  // cell sides removed by the fold, shape [N]

    CellGrid(std::span<const double> x, std::span<const double> y, const Box& box, int nc) : cells(nc) {
        const std::size_t n = x.size();
        const double scale = nc / box.side();
        cell_of.resize(n);
        image_x.resize(n);
        image_y.resize(n);
        start.assign(static_cast<std::size_t>(nc) * nc + 1, 0);
        parallel_for(n, [&](std::size_t i) {
            const double xw = box.fold(x[i], image_x[i]) * scale;
            const double yw = box.fold(y[i], image_y[i]) * scale;
            // A position that folds outside the cell (not finite, or too large to fold: a
            // diverged run) gets -1, refused below, instead of an index out of the grid.
            if (!(xw > -1.0 && xw < kNoCell && yw > -1.0 && yw < kNoCell)) {
                cell_of[i] = -1;
                return;
            }
            const int cx = std::min(static_cast<int>(xw), nc - 1);
            const int cy = std::min(static_cast<int>(yw), nc - 1);
            cell_of[i] = cy * nc + cx;
        });
        for (std::size_t i = 0; i < n; ++i) {
            if (cell_of[i] < 0)
                throw std::runtime_error("disk " + std::to_string(i) + " is at (" + std::to_string(x[i]) + ", " +
                                         std::to_string(y[i]) + "), which does not fold into the box of side " +
                                         std::to_string(box.side()) +
                                         ": the run diverged (a time step too large for its forces or temperature?)");
            ++start[static_cast<std::size_t>(cell_of[i]) + 1];
        }
        for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
        members.resize(n);
        std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
        for (std::size_t i = 0; i < n; ++i)
            members[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[i])]++)] =
                static_cast<std::int32_t>(i);
    }
};

/// floor(side / cell), checked against kMaxCellsPerSide (beyond it the int conversion
/// and the cell indices would overflow).
int cells_per_side(double side, double cell) {
    const double cells = std::floor(side / cell);
    if (!(cells <= NeighborList::kMaxCellsPerSide))
        throw std::invalid_argument("neighbour list: a box of side " + std::to_string(side) + " is " +
                                    std::to_string(cells) + " list ranges wide, more than the " +
                                    std::to_string(NeighborList::kMaxCellsPerSide) +
                                    " a cell grid takes: the system is too dilute (raise phi)");
    return static_cast<int>(cells);
}

}  // namespace

double NeighborList::cell_grid_bytes(double side, double reach) {
    const double cells = std::floor(side / reach);
    return cells >= 5 ? 8.0 * cells * cells : 0.0;
}

void NeighborList::build(std::span<const double> x, std::span<const double> y, std::span<const double> diameter,
                         const Box& box) {
    double max_d = 0.0;
    for (double d : diameter) max_d = std::max(max_d, d);
    const double reach = max_d + skin_;
    if (box.side() < 2.0 * reach)
        throw std::invalid_argument("neighbour list: box side " + std::to_string(box.side()) +
                                    " is below twice the list range " + std::to_string(reach) + "; use more particles");
    const int cells = cells_per_side(box.side(), reach);
    if (cells >= 5)
        build_with_cells(x, y, diameter, box, cells);
    else
        build_all_pairs(x, y, diameter, box);
    finish_build(diameter);
    remember_reference(x, y, box, max_d);
}

void NeighborList::finish_build(std::span<const double> diameter) {
    owner_.resize(neighbor_.size());
    contact_.resize(neighbor_.size());
    parallel_for(first_.size() - 1, [&](std::size_t i) {
        for (auto k = static_cast<std::size_t>(first_[i]); k < static_cast<std::size_t>(first_[i + 1]); ++k) {
            owner_[k] = static_cast<std::int32_t>(i);
            contact_[k] = 0.5 * (diameter[i] + diameter[static_cast<std::size_t>(neighbor_[k])]);
        }
    });
    blocks_.build(first_, neighbor_);
}

void NeighborList::remember_reference(std::span<const double> x, std::span<const double> y, const Box& box,
                                      double max_d) {
    x_ref_.resize(x.size());
    y_ref_.resize(y.size());
    parallel_for(x.size(), [&](std::size_t i) {
        x_ref_[i] = x[i];
        y_ref_[i] = y[i];
    });
    strain_ref_ = box.strain();
    max_diameter_ = max_d;
    valid_ = true;
    ++builds_;
}

void NeighborList::build_all_pairs(std::span<const double> x, std::span<const double> y,
                                   std::span<const double> diameter, const Box& box) {
    const std::size_t n = x.size();
    const double side = box.side();
    first_.assign(n + 1, 0);
    neighbor_.clear();
    shift_x_.clear();
    shift_y_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 1; j < n; ++j) {
            const double dx = x[i] - x[j], dy = y[i] - y[j];
            const double ny = std::nearbyint(dy / side);
            const double nx = std::nearbyint(box.lab_x(dx, dy - ny * side) / side);
            const Vec2 r = box.lab(dx - nx * side, dy - ny * side);
            const double range = 0.5 * (diameter[i] + diameter[j]) + skin_;
            if (norm2(r) < range * range) {
                neighbor_.push_back(static_cast<std::int32_t>(j));
                shift_x_.push_back(-nx * side);
                shift_y_.push_back(-ny * side);
            }
        }
        first_[i + 1] = static_cast<std::int32_t>(neighbor_.size());
    }
}

void NeighborList::build_with_cells(std::span<const double> x, std::span<const double> y,
                                    std::span<const double> diameter, const Box& box, int nc) {
    const std::size_t n = x.size();
    const double side = box.side();
    const CellGrid grid(x, y, box, nc);
    // Half stencil in sheared coordinates: a pair closer than the list range in the lab
    // has |dy| < w and |dx| ≤ (1 + |γ|) range < 2w, so rows 0 and +1 and columns ±2 suffice;
    // listing (0,0) with j > i, (1,0), (2,0) and (−2..2, +1) visits each cell pair once.
    // When (1 + |γ|) reach ≤ w (always at γ = 0: minimisations, compression) columns ±1
    // suffice: 5 cells instead of 8.
    static constexpr int kWide[8][2] = {{0, 0}, {1, 0}, {2, 0}, {-2, 1}, {-1, 1}, {0, 1}, {1, 1}, {2, 1}};
    static constexpr int kNarrow[5][2] = {{0, 0}, {1, 0}, {-1, 1}, {0, 1}, {1, 1}};
    double max_d = 0.0;
    for (double d : diameter) max_d = std::max(max_d, d);
    const bool narrow = (1.0 + std::abs(box.strain())) * (max_d + skin_) <= side / nc;
    const std::span<const int[2]> stencil = narrow ? std::span<const int[2]>(kNarrow) : std::span<const int[2]>(kWide);
    // The candidates of disk i, in the order the list keeps them (stencil, then cell order).
    const auto visit = [&](std::size_t i, auto&& keep) {
        const int ci = grid.cell_of[i];
        const int cx = ci % nc, cy = ci / nc;
        const double kxi = grid.image_x[i], kyi = grid.image_y[i];
        for (const auto& offset : stencil) {
            int nx = cx + offset[0], ny = cy + offset[1];
            int wx = 0, wy = 0;  // which periodic image of the neighbour cell
            if (nx < 0) {
                nx += nc;
                wx = -1;
            }
            if (nx >= nc) {
                nx -= nc;
                wx = 1;
            }
            if (ny >= nc) {
                ny -= nc;
                wy = 1;
            }
            const int cj = ny * nc + nx;
            for (auto k = grid.start[static_cast<std::size_t>(cj)]; k < grid.start[static_cast<std::size_t>(cj) + 1];
                 ++k) {
                const auto j = static_cast<std::size_t>(grid.members[static_cast<std::size_t>(k)]);
                if (cj == ci && j <= i) continue;
                // Sheared shift that takes x_j to the image sitting in cell (cx+ox, cy+oy).
                const double sx = (grid.image_x[j] - kxi - wx) * side;
                const double sy = (grid.image_y[j] - kyi - wy) * side;
                const Vec2 r = box.lab(x[i] - x[j] + sx, y[i] - y[j] + sy);
                const double range = 0.5 * (diameter[i] + diameter[j]) + skin_;
                if (norm2(r) < range * range) keep(static_cast<std::int32_t>(j), sx, sy);
            }
        }
    };
    first_.assign(n + 1, 0);
    neighbor_.clear();
    shift_x_.clear();
    shift_y_.clear();
    if (n >= kThreadedLoopMin && kernel_threads() > 1) {
        // Each thread lists a contiguous range of owners; the ranges are then laid end to end
        // in owner order: the list of the one-thread build, whatever the split.
        std::vector<std::int32_t> count(n);
        const TimedRegion timed;
#pragma omp parallel
        {
            const auto t = static_cast<std::size_t>(omp_get_thread_num());
            const auto threads = static_cast<std::size_t>(omp_get_num_threads());
            const std::size_t lo = n * t / threads, hi = n * (t + 1) / threads;
            std::vector<std::int32_t> nb;
            std::vector<double> bx, by;
            nb.reserve((hi - lo) * 4);
            bx.reserve((hi - lo) * 4);
            by.reserve((hi - lo) * 4);
            for (std::size_t i = lo; i < hi; ++i) {
                const std::size_t before = nb.size();
                visit(i, [&](std::int32_t j, double sx, double sy) {
                    nb.push_back(j);
                    bx.push_back(sx);
                    by.push_back(sy);
                });
                count[i] = static_cast<std::int32_t>(nb.size() - before);
            }
#pragma omp barrier
#pragma omp single
            {
                for (std::size_t i = 0; i < n; ++i) first_[i + 1] = first_[i] + count[i];
                neighbor_.resize(static_cast<std::size_t>(first_[n]));
                shift_x_.resize(neighbor_.size());
                shift_y_.resize(neighbor_.size());
            }  // (a barrier)
            if (lo < hi) {
                const auto at = static_cast<std::ptrdiff_t>(first_[lo]);
                std::copy(nb.begin(), nb.end(), neighbor_.begin() + at);
                std::copy(bx.begin(), bx.end(), shift_x_.begin() + at);
                std::copy(by.begin(), by.end(), shift_y_.begin() + at);
            }
        }
        return;
    }
    neighbor_.reserve(n * 4);
    shift_x_.reserve(n * 4);
    shift_y_.reserve(n * 4);
    for (std::size_t i = 0; i < n; ++i) {
        visit(i, [&](std::int32_t j, double sx, double sy) {
            neighbor_.push_back(j);
            shift_x_.push_back(sx);
            shift_y_.push_back(sy);
        });
        first_[i + 1] = static_cast<std::int32_t>(neighbor_.size());
    }
}

bool verlet_rule_broken(std::span<const double> x, std::span<const double> y, std::span<const double> x_ref,
                        std::span<const double> y_ref, double strain, double strain_ref, double reach, double skin) {
    if (x.size() != x_ref.size()) return true;
    // 2 max|M(γ)δs| + |Δγ| reach > skin  ⇔  some |M(γ)δs|² > ((skin − affine)/2)²
    const double affine = std::abs(strain - strain_ref) * reach;
    const double allowed = 0.5 * (skin - affine);
    if (allowed <= 0.0) return true;
    const double allowed2 = allowed * allowed;
    int moved_too_far = 0;  // an OR over all particles, written to vectorise (no early exit)
    const auto n = static_cast<long>(x.size());
    const bool threaded = n >= static_cast<long>(kThreadedLoopMin) && kernel_threads() > 1;
    auto moved = [&](long il) {
        const auto i = static_cast<std::size_t>(il);
        const double dy = y[i] - y_ref[i];
        const double dx = x[i] - x_ref[i] + strain * dy;
        return static_cast<int>(dx * dx + dy * dy > allowed2);
    };
    if (threaded) {
        const TimedRegion timed;
#pragma omp parallel for schedule(static) reduction(| : moved_too_far)
        for (long il = 0; il < n; ++il) moved_too_far |= moved(il);
    } else {  // no region: even one of one thread costs a system call (pair_forces.hpp)
        for (long il = 0; il < n; ++il) moved_too_far |= moved(il);
    }
    return moved_too_far != 0;
}

bool NeighborList::needs_rebuild(std::span<const double> x, std::span<const double> y, const Box& box) const {
    return !valid_ || verlet_rule_broken(x, y, x_ref_, y_ref_, box.strain(), strain_ref_, max_diameter_ + skin_, skin_);
}

std::vector<std::int32_t> spatial_order(const Particles& p, const Box& box, double cell) {
    const int nc = std::max(1, cells_per_side(box.side(), cell));
    const CellGrid grid(p.x, p.y, box, nc);
    return grid.members;
}

}  // namespace jamsim

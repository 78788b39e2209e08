#pragma once
#include <cmath>
#include <span>
#include <stdexcept>

#include "jamsim/core/vec2.hpp"

namespace jamsim {

/// Square periodic cell of side L with Lees–Edwards shear, in sheared coordinates
/// (thesis §4.2.4). Particles store sheared coordinates (x, y); the lab position is
/// r = (x + γ y, y). In sheared coordinates every image of a particle sits at
/// (x + mL, y + nL) for integers m, n whatever γ is, so the cell is a plain square torus;
/// γ enters only when a sheared separation is turned into a lab-frame one.
///
/// γ is kept in [−1/2, 1/2): when shearing carries it past 1/2 it drops by 1 and every
/// particle's sheared x becomes x + y (the same lab positions, since a shift of L in x per
/// row is a lattice vector). This class owns all of that logic; nothing else in jamsim
/// mentions periodic images.
class Box {
  public:
    /// side: L in units of the small diameter; strain: initial γ (wrapped into [−1/2, 1/2)).
    explicit Box(double side, double strain = 0.0) : side_(side), inv_side_(1.0 / side) {
        if (!(side > 0.0) || !std::isfinite(side)) throw std::invalid_argument("Box: side must be positive and finite");
        strain_ = strain;
        wrap_count_for(strain_);
    }

    double side() const { return side_; }
    double area() const { return side_ * side_; }
    /// Current Lees–Edwards strain γ in [−1/2, 1/2) (between steps).
    double strain() const { return strain_; }

    /// Lab-frame minimum-image separation for a sheared-coordinate difference (dx, dy).
    /// Exact for separations shorter than L/2 (the only ones the force loop needs).
    Vec2 min_image(double dx, double dy) const {
        dy -= side_ * std::nearbyint(dy * inv_side_);
        double rx = dx + strain_ * dy;
        rx -= side_ * std::nearbyint(rx * inv_side_);
        return {rx, dy};
    }

    /// Lab-frame separation for a sheared difference (dx, dy) that already includes the
    /// right image shift (as stored by the neighbour list).
    Vec2 lab(double dx, double dy) const { return {dx + strain_ * dy, dy}; }

    /// The sheared-coordinate displacement of a lab-frame displacement (dx, dy).
    Vec2 sheared(double dx, double dy) const { return {dx - strain_ * dy, dy}; }

    /// Lab-frame x of a point with sheared coordinates (x, y).
    double lab_x(double x, double y) const { return x + strain_ * y; }

    /// Integer number of cell sides to subtract so that a coordinate lands in [0, L).
    double image_of(double coordinate) const { return std::floor(coordinate * inv_side_); }

    /// Fold one coordinate into [0, L): returns the folded value and sets `image` to the
    /// number of cell sides removed (coordinate = folded + image·L up to rounding). Cell
    /// binning and image shifts must both use this one rule, so that a value that rounds
    /// onto L is treated as 0 of the next image by both.
    double fold(double coordinate, double& image) const {
        image = image_of(coordinate);
        double folded = coordinate - side_ * image;
        if (folded >= side_) {  // rounding can leave exactly L
            folded -= side_;
            image += 1.0;
        }
        return folded;
    }

    /// Map (x, y) into the primary cell [0, L)² without changing the lab position
    /// (modulo lattice vectors).
    void wrap_into_cell(double& x, double& y) const {
        double image = 0.0;
        y = fold(y, image);
        x = fold(x, image);
    }

    /// Set γ during a step (a Heun predictor, say); may lie slightly outside [−1/2, 1/2).
    /// Call finish_shear() at the end of the step to restore the invariant.
    void set_strain_unwrapped(double strain) { strain_ = strain; }

    /// Bring γ back into [−1/2, 1/2) after shearing. Returns k, the number of unit wraps
    /// (γ_new = γ_old − k); if k ≠ 0, positions must go through remap_after_wrap(k, ...).
    [[nodiscard]] int finish_shear() { return wrap_count_for(strain_); }

    /// Rewrite sheared x so that lab positions are unchanged after γ dropped by k:
    /// x + γ y = x' + (γ − k) y  ⇒  x' = x + k y.
    void remap_after_wrap(int k, std::span<double> x, std::span<const double> y) const {
        const double kk = k;
        for (std::size_t i = 0; i < x.size(); ++i) x[i] += kk * y[i];
    }

  private:
    int wrap_count_for(double& strain) const {
        const double k = std::floor(strain + 0.5);  // γ − k ∈ [−1/2, 1/2)
        strain -= k;
        return static_cast<int>(k);
    }

    double side_;
    double inv_side_;
    double strain_ = 0.0;
};

}  // namespace jamsim

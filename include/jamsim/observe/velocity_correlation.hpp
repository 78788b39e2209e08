#pragma once
#include <stdexcept>
#include <vector>

#include "jamsim/core/system.hpp"

namespace jamsim {

/// Spatial correlation of the transverse non-affine velocity along the flow (thesis
/// eq. 4.23): g_y(x) = ⟨u_y(r_i) u_y(r_i + x x̂)⟩ / ⟨u_y²⟩.
/// Estimator: pairs of disks whose lab y separation is below strip/2 (a thin horizontal
/// strip, minimum image) are binned by their lab x distance |x| < L/2 in bins of width
/// `bin_width`; each bin averages u_y,i u_y,j over all pairs and samples accumulated, and is
/// divided by the mean of u_y² over the same samples. Uses particles.uy (the model fills it).
class VelocityCorrelation {
  public:
    VelocityCorrelation(double side, double bin_width = 0.25, double strip = 1.0);

    /// Add one sample. O(N · N strip / L) with a sweep over disks sorted by y.
    void accumulate(const System& sys);

    std::size_t bins() const { return sum_.size(); }
    std::vector<double> bin_centres() const;
    /// g_y at the bin centres (NaN for a bin without pairs, or before any sample).
    std::vector<double> g() const;

    /// The accumulated sums (a checkpoint saves them; restore() continues from them).
    struct Sums {
        std::vector<double> sum, count;  ///< per bin, shape [bins]
        double uy2_sum = 0.0, uy2_count = 0.0;
    };
    Sums sums() const { return {sum_, count_, uy2_sum_, uy2_count_}; }
    /// Continue from saved sums; throws std::invalid_argument if their bins do not fit.
    void restore(const Sums& s);

    /// Number of bins for a box of this side (used to size archive datasets).
    static std::size_t bins_for(double side, double bin_width = 0.25);

  private:
    double side_, bin_width_, strip_;
    std::vector<double> sum_, count_;
    double uy2_sum_ = 0.0, uy2_count_ = 0.0;
};

}  // namespace jamsim

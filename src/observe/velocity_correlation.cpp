#include "jamsim/observe/velocity_correlation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "jamsim/parallel/reduce.hpp"

namespace jamsim {

std::size_t VelocityCorrelation::bins_for(double side, double bin_width) {
    return static_cast<std::size_t>(std::floor(0.5 * side / bin_width));
}

VelocityCorrelation::VelocityCorrelation(double side, double bin_width, double strip)
    : side_(side), bin_width_(bin_width), strip_(strip), sum_(bins_for(side, bin_width), 0.0),
      count_(sum_.size(), 0.0) {}

void VelocityCorrelation::restore(const Sums& s) {
    if (s.sum.size() != sum_.size() || s.count.size() != count_.size())
        throw std::invalid_argument("g_y sums of " + std::to_string(s.sum.size()) + " bins do not fit " +
                                    std::to_string(sum_.size()) + " bins");
    sum_ = s.sum;
    count_ = s.count;
    uy2_sum_ = s.uy2_sum;
    uy2_count_ = s.uy2_count;
}

void VelocityCorrelation::accumulate(const System& sys) {
    const Particles& p = sys.particles;
    const std::size_t n = p.size();
    std::vector<double> yw(n);
    parallel_for(n, [&](std::size_t i) {
        double xw = p.x[i];
        yw[i] = p.y[i];
        sys.box.wrap_into_cell(xw, yw[i]);
    });
    for (std::size_t i = 0; i < n; ++i) uy2_sum_ += p.uy[i] * p.uy[i];
    uy2_count_ += static_cast<double>(n);
    // Disks by height, ties by index: a strict order, so any sort gives this one.
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t{0});
    const auto below = [&](std::size_t a, std::size_t b) { return yw[a] < yw[b] || (yw[a] == yw[b] && a < b); };
    parallel_sort(order, below);
    const double half_strip = 0.5 * strip_, half_side = 0.5 * side_;
    // Each disk's partners above it in y (wrapping past the top), each unordered pair once,
    // for disks order[a0 .. a1), into bins `sum`, `count`.
    auto add_pairs = [&](std::size_t a0, std::size_t a1, double* sum, double* count) {
        for (std::size_t a = a0; a < a1; ++a) {
            const std::size_t i = order[a];
            for (std::size_t step = 1; step < n; ++step) {
                const std::size_t j = order[(a + step) % n];
                double dy = yw[j] - yw[i];
                if (dy < 0) dy += side_;
                if (dy >= half_strip) break;
                const Vec2 r = sys.box.min_image(p.x[i] - p.x[j], p.y[i] - p.y[j]);
                const double ax = std::abs(r.x);
                if (std::abs(r.y) >= half_strip || ax >= half_side) continue;
                const auto bin = static_cast<std::size_t>(ax / bin_width_);
                if (bin >= sum_.size()) continue;
                sum[bin] += p.uy[i] * p.uy[j];
                count[bin] += 1.0;
            }
        }
    };
    // Fixed blocks of kReduceBlock disks in height order (never a function of the thread
    // count): one block adds straight into the sums; several add their own bins, which are
    // then added in block order. The same bits on any number of threads.
    const std::size_t blocks = (n + kReduceBlock - 1) / kReduceBlock, bins = sum_.size();
    if (blocks <= 1) {
        add_pairs(0, n, sum_.data(), count_.data());
        return;
    }
    std::vector<double> block_sum(blocks * bins, 0.0), block_count(blocks * bins, 0.0);
    parallel_for_blocks(blocks, [&](std::size_t b) {
        add_pairs(b * kReduceBlock, std::min(n, (b + 1) * kReduceBlock), block_sum.data() + b * bins,
                  block_count.data() + b * bins);
    });
    for (std::size_t b = 0; b < blocks; ++b)
        for (std::size_t k = 0; k < bins; ++k) {
            sum_[k] += block_sum[b * bins + k];
            count_[k] += block_count[b * bins + k];
        }
}

std::vector<double> VelocityCorrelation::bin_centres() const {
    std::vector<double> x(sum_.size());
    for (std::size_t k = 0; k < x.size(); ++k) x[k] = (static_cast<double>(k) + 0.5) * bin_width_;
    return x;
}

std::vector<double> VelocityCorrelation::g() const {
    std::vector<double> out(sum_.size(), std::numeric_limits<double>::quiet_NaN());
    if (uy2_count_ == 0 || uy2_sum_ == 0) return out;
    const double norm = uy2_sum_ / uy2_count_;
    for (std::size_t k = 0; k < out.size(); ++k)
        if (count_[k] > 0) out[k] = sum_[k] / count_[k] / norm;
    return out;
}

}  // namespace jamsim

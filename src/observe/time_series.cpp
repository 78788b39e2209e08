#include "jamsim/observe/time_series.hpp"

#include <limits>

namespace jamsim {

double mean_after(const TimeSeries& ts, double Sample::*member, double from_strain, bool in_time) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t k = 0; k < ts.size(); ++k) {
        if ((in_time ? ts[k].time : ts[k].strain) < from_strain) continue;
        sum += ts[k].*member;
        ++count;
    }
    return count ? sum / static_cast<double>(count) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace jamsim

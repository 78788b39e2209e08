#include "jamsim/core/memory.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <string>

namespace jamsim {

double available_memory() {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    double kb = 0;
    while (in >> key >> kb >> unit)
        if (key == "MemAvailable:") return kb * 1024.0;
    return std::numeric_limits<double>::quiet_NaN();
}

std::string show_bytes(double bytes) {
    if (!std::isfinite(bytes)) return "unknown";
    const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
    int k = 0;
    while (std::abs(bytes) >= 1000.0 && k < 6) {
        bytes /= 1000.0;
        ++k;
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, k == 0 ? "%.0f %s" : "%.3g %s", bytes, units[k]);
    return buf;
}

}  // namespace jamsim

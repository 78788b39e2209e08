#pragma once
// This node's memory, which every memory check plans against, and sizes in words.
#include <string>

namespace jamsim {

/// This node's available memory in bytes (MemAvailable in /proc/meminfo); NaN where unknown.
double available_memory();

/// The share of the available memory that jamsim plans to use (the rest is the system's).
inline constexpr double kMemoryMargin = 0.8;

/// A size in bytes as a person reads it: "1.16 GB", "512 B"; "unknown" when not finite.
std::string show_bytes(double bytes);

}  // namespace jamsim

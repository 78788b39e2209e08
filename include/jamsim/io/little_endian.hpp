#pragma once
// HDF5 stores its addresses and lengths as little-endian unsigned integers; the checks that read
// a file's bytes before HDF5 does (the superblock, the global heaps) decode them here.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace jamsim {

/// The little-endian unsigned integer of `bytes` (at most 8) bytes at `at` of `data`.
inline std::uint64_t little_endian(std::string_view data, std::size_t at, std::size_t bytes) {
    std::uint64_t v = 0;
    for (std::size_t k = 0; k < bytes; ++k)
        v |= static_cast<std::uint64_t>(static_cast<unsigned char>(data[at + k])) << (8 * k);
    return v;
}

}  // namespace jamsim

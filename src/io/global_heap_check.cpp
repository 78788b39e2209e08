#include "jamsim/io/global_heap_check.hpp"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string_view>

#include "jamsim/io/little_endian.hpp"

namespace jamsim {

namespace {

/// The walk of H5HG's cache deserialiser (HDF5 1.10, 8-byte lengths): after the 16-byte
/// header ("GCOL", version 1, 3 reserved bytes, the collection's size), objects of a 16-byte
/// header (index 2, references 2, reserved 4, size 8) and their data padded to 8 bytes; index
/// 0 is the free space, its size the rest. "" when the walk ends at the collection's end.
std::string walk_collection(std::string_view file, std::size_t at, std::uint64_t size) {
    constexpr std::size_t kHeader = 16, kObjectHeader = 16;
    std::size_t p = at + kHeader;
    const std::size_t end = at + size;
    while (p < end) {
        if (p + kObjectHeader > end) return "";  // too little left for an object: free space
        const std::uint64_t index = little_endian(file, p, 2);
        const std::uint64_t object = little_endian(file, p + 8, 8);
        const std::uint64_t need = index > 0 ? kObjectHeader + ((object + 7) / 8) * 8 : object;
        if (need == 0 || need > end - p)
            return "the global heap at byte " + std::to_string(at) + " holds an object of size " +
                   std::to_string(object) + " at byte " + std::to_string(p) + (need == 0 ? "" : ", past its end");
        p += need;
    }
    return "";
}

}  // namespace

std::string damaged_global_heap(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return "";
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string_view file(bytes);
    constexpr std::size_t kHeader = 16, kLeast = 4096;  // HDF5 makes collections of at least 4 KiB
    for (std::size_t at = file.find("GCOL"); at != std::string_view::npos; at = file.find("GCOL", at + 1)) {
        if (at + kHeader > file.size() || file[at + 4] != 1) continue;  // version 1 only
        const std::uint64_t size = little_endian(file, at + 8, 8);
        if (size < kLeast || size > file.size() - at) continue;  // not a collection's header
        if (std::string why = walk_collection(file, at, size); !why.empty()) return why;
    }
    return "";
}

}  // namespace jamsim

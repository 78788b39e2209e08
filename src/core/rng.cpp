#include "jamsim/core/rng.hpp"

namespace jamsim {

std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> c, std::array<std::uint32_t, 2> k) {
    constexpr std::uint32_t kMul0 = 0xD2511F53u, kMul1 = 0xCD9E8D57u;
    constexpr std::uint32_t kWeyl0 = 0x9E3779B9u, kWeyl1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const std::uint64_t p0 = std::uint64_t{kMul0} * c[0];
        const std::uint64_t p1 = std::uint64_t{kMul1} * c[2];
        const auto hi0 = static_cast<std::uint32_t>(p0 >> 32), lo0 = static_cast<std::uint32_t>(p0);
        const auto hi1 = static_cast<std::uint32_t>(p1 >> 32), lo1 = static_cast<std::uint32_t>(p1);
        c = {hi1 ^ c[1] ^ k[0], lo1, hi0 ^ c[3] ^ k[1], lo0};
        k[0] += kWeyl0;
        k[1] += kWeyl1;
    }
    return c;
}

RngStream::RngStream(std::uint64_t seed, std::uint64_t identity, RngPurpose purpose) : seed_(seed) {
    // splitmix64's finaliser: a bijection of 64 bits with full avalanche.
    std::uint64_t z = identity ^ (static_cast<std::uint64_t>(purpose) * 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    stream_ = z ^ (z >> 31);
}

std::array<double, 2> RngStream::uniform2(std::uint32_t index, std::uint32_t sub) const {
    const auto key =
        std::array<std::uint32_t, 2>{static_cast<std::uint32_t>(seed_), static_cast<std::uint32_t>(seed_ >> 32)};
    const auto r =
        philox4x32({static_cast<std::uint32_t>(stream_), static_cast<std::uint32_t>(stream_ >> 32), index, sub}, key);
    constexpr double k2m53 = 1.0 / 9007199254740992.0;  // 2^-53
    const auto to_unit = [](std::uint32_t hi, std::uint32_t lo) {
        const std::uint64_t bits = (std::uint64_t{hi} << 21) ^ (std::uint64_t{lo} >> 11);
        return static_cast<double>(bits) * k2m53;
    };
    return {to_unit(r[0], r[1]), to_unit(r[2], r[3])};
}

}  // namespace jamsim

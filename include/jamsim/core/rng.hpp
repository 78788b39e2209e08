#pragma once
#include <array>
#include <cstdint>

namespace jamsim {

/// Every use of random numbers in jamsim has its own purpose id (HOOMD's RNGIdentifiers
/// idea): streams for different purposes never overlap, and adding a purpose never
/// changes the numbers another purpose draws.
enum class RngPurpose : std::uint32_t {
    InitialPositions = 1,
    ThermalNoise = 2,          ///< COOL: Langevin noise, index = disk tag, sub = step
    TestConfiguration = 1000,  ///< random configurations in tests
};

/// Philox4x32-10 (Salmon et al., SC'11): a counter-based generator. The output is a pure
/// function of (key, counter), so a replica's random numbers depend only on
/// (seed, identity, purpose, index) and never on rank count or scheduling.
std::array<std::uint32_t, 4> philox4x32(std::array<std::uint32_t, 4> counter, std::array<std::uint32_t, 2> key);

/// What a replica's random numbers are keyed by: its seed and its identity, a 64-bit hash of
/// its model and physical parameters (run/model_registry.hpp: replica_identity). Never its
/// position in a sweep, so the same replica has the same numbers in any campaign.
struct RandomKey {
    std::uint64_t seed = 1;
    std::uint64_t identity = 0;
};

/// A stream of uniform doubles keyed by (seed, identity, purpose): draw k of `index` is
/// philox(key = seed, counter = {stream, index, sub}) with the 64-bit stream a bijective mix
/// of (identity, purpose), so streams of different purposes or identities never coincide
/// except by a 2^-64 chance.
class RngStream {
  public:
    RngStream(std::uint64_t seed, std::uint64_t identity, RngPurpose purpose);
    RngStream(const RandomKey& key, RngPurpose purpose) : RngStream(key.seed, key.identity, purpose) {}

    /// Two independent uniform doubles in [0, 1) (53 random bits each) for `index`
    /// and sub-counter `sub`.
    std::array<double, 2> uniform2(std::uint32_t index, std::uint32_t sub = 0) const;

  private:
    std::uint64_t seed_;
    std::uint64_t stream_;
};

}  // namespace jamsim

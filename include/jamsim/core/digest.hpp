#pragma once
// A 64-bit digest of data, for recognising a file or a state that changed since it was
// recorded (checkpoints, the initial states a campaign started from). FNV-1a's scheme on
// 8-byte words (bytes for text), then splitmix64's finaliser. Not cryptographic: it guards
// against damage and mix-ups, not against forgery.
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace jamsim {

class Digest {
  public:
    void add(std::uint64_t word) { h_ = (h_ ^ word) * 0x100000001b3ULL; }
    void add(std::int64_t v) { add(static_cast<std::uint64_t>(v)); }
    void add(double v) {  // the bits: -0.0 and 0.0, or two NaNs, differ
        std::uint64_t w;
        std::memcpy(&w, &v, sizeof w);
        add(w);
    }
    void add(std::string_view text) {
        add(static_cast<std::uint64_t>(text.size()));
        add_bytes(text);
    }
    /// The bytes alone, without their count: add(text) of a text that arrives in pieces is
    /// add(its whole size) and then add_bytes of each piece.
    void add_bytes(std::string_view piece) {
        for (const unsigned char c : piece) h_ = (h_ ^ c) * 0x100000001b3ULL;
    }
    void add(const std::vector<double>& v) {
        add(static_cast<std::uint64_t>(v.size()));
        for (const double x : v) add(x);
    }
    void add(const std::vector<std::int32_t>& v) {
        add(static_cast<std::uint64_t>(v.size()));
        for (const std::int32_t x : v) add(static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)));
    }
    /// Never 0, so that 0 can mean "none recorded".
    std::uint64_t value() const {
        std::uint64_t z = h_;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        z ^= z >> 31;
        return z == 0 ? 1 : z;
    }

  private:
    std::uint64_t h_ = 0xcbf29ce484222325ULL;
};

}  // namespace jamsim

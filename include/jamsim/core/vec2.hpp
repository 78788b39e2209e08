#pragma once

namespace jamsim {

/// A plain 2-vector; used for single separations, never for per-particle storage
/// (particle state is a struct of arrays, see Particles).
struct Vec2 {
    double x = 0.0;
    double y = 0.0;
};

inline double norm2(Vec2 v) { return v.x * v.x + v.y * v.y; }

}  // namespace jamsim

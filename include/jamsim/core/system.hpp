#pragma once
#include <cstdint>

#include "jamsim/core/box.hpp"
#include "jamsim/core/particles.hpp"

namespace jamsim {

/// How the disk sizes are drawn: a 50:50 mixture of diameters 1 and `size_ratio`
/// (size_ratio = 1 gives a monodisperse system).
struct SizeMix {
    double size_ratio = 1.4;
};

/// Side L of the square cell that gives packing fraction phi = Σ π d_i² / (4 L²).
double box_side_for(const Particles& p, double phi);

/// Side L for n disks of the 50:50 mixture (size_ratio 1: monodisperse) at phi.
double box_side_for(std::int64_t n, double phi, double size_ratio);

/// Packing fraction of the particles in the box: Σ π d_i² / (4 L²).
double packing_fraction(const Particles& p, const Box& box);

/// Particles + box: the complete configuration of one replica.
struct System {
    Particles particles;
    Box box;
};

/// N disks (first half small d = 1, second half large d = size_ratio) at uniformly random
/// positions, keyed by (seed, identity) (core/rng.hpp: RandomKey): the same inputs give the
/// same configuration bitwise on any machine. N must be even unless size_ratio == 1.
System random_system(std::int64_t n, double phi, SizeMix mix, std::uint64_t seed, std::uint64_t identity);

}  // namespace jamsim

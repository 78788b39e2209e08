#pragma once
// LAMMPS data files: a final configuration out (`jamsim export`), an initial configuration in
// ([run] initial = "FILE.data", `jamsim replica --initial FILE.data`).
//
// The file jamsim writes (campaigns/README.md, "Exporting and importing configurations"):
// `atom_style sphere`
// (Atoms line `id type diameter density x y z`), 2 atom types (1 = small, d = 1; 2 = large,
// d = size_ratio), density 1, the sheared cell as LAMMPS's tilted box with xlo = ylo = 0,
// xhi = yhi = L, xy = γL (γ in [−1/2, 1/2), as jamsim keeps it), zlo zhi = −0.5 0.5, and lab
// positions x = x_sheared + γ y, z = 0. Atom id = particle index + 1.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/run/replica.hpp"

namespace jamsim {

/// A file that is not a LAMMPS data file jamsim can use; the message names the file, the line
/// or section, the value and what is allowed.
struct LammpsDataError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Write `c` (by particle index, sheared coordinates) to `path` as described above.
/// `title` becomes the file's first line (newlines replaced). Writes `path` itself: the
/// caller writes to a temporary name and renames. Throws std::runtime_error on I/O failure.
void write_lammps_data(const std::string& path, const FinalConfiguration& c, const std::string& title);

/// What a LAMMPS data file holds, as written in it (lab frame).
struct LammpsData {
    std::int64_t atoms = 0;       ///< header "atoms"
    std::int64_t atom_types = 0;  ///< header "atom types"
    double xlo = 0, xhi = 0, ylo = 0, yhi = 0, zlo = 0, zhi = 0;
    double xy = 0, xz = 0, yz = 0;  ///< tilt factors (0 without an "xy xz yz" line)
    std::string atom_style;         ///< "sphere" or "atomic"
    std::vector<std::int64_t> id;   ///< per atom, in file order
    std::vector<int> type;
    std::vector<double> diameter;  ///< sphere only (empty for atomic)
    std::vector<double> x, y, z;
};

/// Parse the header and the Atoms section (atom_style sphere or atomic, with or without image
/// flags; other sections such as Masses and Velocities are skipped). Throws LammpsDataError.
LammpsData read_lammps_data(const std::string& path);

/// The configuration as a jamsim System of `n` disks with the 50:50 mixture of `size_ratio`:
/// disks in the order (type, atom id), small ones first as jamsim creates them; sheared
/// coordinates x_s = (x − xlo) − γ (y − ylo), γ = xy / L wrapped into [−1/2, 1/2), folded into
/// the cell. Refused (LammpsDataError naming `path`): another atom count than n; types other
/// than 1 and 2; a composition other than n/2 + n/2 (size_ratio ≠ 1); diameters (sphere) that
/// differ within a type or from 1 (type 1) and size_ratio (type 2), so that the two types
/// overlap; a cell that is not square or is tilted other than by xy (not a simple shear);
/// z ≠ 0; duplicate atom ids.
System system_from_lammps_data(const LammpsData& data, const std::string& path, std::int64_t n, double size_ratio);

/// True when the file starts with the HDF5 signature (an archive), false otherwise (a text
/// file such as a LAMMPS data file). Throws LammpsDataError when it cannot be read.
bool is_hdf5_file(const std::string& path);

}  // namespace jamsim

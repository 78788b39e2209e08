// LAMMPS data files: a configuration written by jamsim export reads back as the same start
// state (bitwise at γ = 0; at γ ≠ 0 the side, y, diameters and order bitwise, γ and x to
// within the rounding of γL and x + γy that the file's lab coordinates carry), and every
// refusal of the importer names the file and what is allowed.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <string_view>

#include "jamsim/core/digest.hpp"
#include "jamsim/core/system.hpp"
#include "jamsim/io/initial_states.hpp"
#include "jamsim/io/lammps_data.hpp"
#include "jamsim/run/replica.hpp"

using namespace jamsim;

namespace {

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("jamsim_test_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

/// A random configuration (N disks of the 50:50 mixture) at strain `gamma`, in output form.
FinalConfiguration configuration(double gamma, std::int64_t n = 200) {
    System sys = random_system(n, 0.84, SizeMix{1.4}, 7, 11);
    sys.box = Box(sys.box.side(), gamma);
    return final_configuration(sys);
}

std::string write_text(const std::string& name, const std::string& text) {
    const std::string path = temp_path(name);
    std::ofstream(path) << text;
    return path;
}

/// A jamsim-written data file with one substitution applied to its text.
std::string edited(const FinalConfiguration& c, const std::string& name, const std::regex& from,
                   const std::string& to) {
    const std::string path = temp_path(name + ".orig");
    write_lammps_data(path, c, "test");
    std::ifstream in(path);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(path);
    const std::string out = std::regex_replace(text, from, to, std::regex_constants::format_first_only);
    EXPECT_NE(out, text) << "the edit did not apply";
    return write_text(name, out);
}

std::string refusal(const std::string& path, std::int64_t n = 200, double size_ratio = 1.4) {
    try {
        (void)system_from_lammps_data(read_lammps_data(path), path, n, size_ratio);
    } catch (const LammpsDataError& e) {
        std::filesystem::remove(path);
        return e.what();
    }
    std::filesystem::remove(path);
    return "";
}

}  // namespace

TEST(LammpsData, RoundTripIsBitwiseWithoutShear) {
    const FinalConfiguration c = configuration(0.0);
    const std::string path = temp_path("unsheared.data");
    write_lammps_data(path, c, "round trip");
    const System back = system_from_lammps_data(read_lammps_data(path), path, 200, 1.4);
    std::filesystem::remove(path);
    const FinalConfiguration d = final_configuration(back);
    EXPECT_EQ(d.box_side, c.box_side);
    EXPECT_EQ(d.box_strain, 0.0);
    EXPECT_EQ(d.x, c.x);
    EXPECT_EQ(d.y, c.y);
    EXPECT_EQ(d.diameter, c.diameter);
}

TEST(LammpsData, RoundTripOfAShearedCell) {
    for (double gamma : {0.23, -0.5, 0.4999, -0.137}) {
        const FinalConfiguration c = configuration(gamma);
        const std::string path = temp_path("sheared.data");
        write_lammps_data(path, c, "round trip");
        const LammpsData data = read_lammps_data(path);
        const System back = system_from_lammps_data(data, path, 200, 1.4);
        std::filesystem::remove(path);
        const FinalConfiguration d = final_configuration(back);
        EXPECT_EQ(data.atom_style, "sphere");
        EXPECT_EQ(d.box_side, c.box_side);
        // xy = γL is chosen so that xy / L gives γ back where a double does (not always)
        EXPECT_LE(std::abs(d.box_strain - c.box_strain), std::abs(std::nextafter(gamma, 1.0) - gamma))
            << "gamma " << gamma;
        EXPECT_EQ(d.y, c.y);
        EXPECT_EQ(d.diameter, c.diameter);
        std::size_t exact = 0;
        const double ulp = std::nextafter(c.box_side, 2 * c.box_side) - c.box_side;
        for (std::size_t i = 0; i < c.x.size(); ++i) {
            EXPECT_LE(std::abs(d.x[i] - c.x[i]), ulp) << "disk " << i << " gamma " << gamma;
            exact += d.x[i] == c.x[i];
        }
        // Many lab x values can be chosen so that x - γy gives the sheared x back bitwise.
        EXPECT_GT(exact, c.x.size() / 3) << "gamma " << gamma;
    }
}

TEST(LammpsData, ReadsAtomicStyleOrderedByTypeThenId) {
    // Ids out of order, types interleaved, a shifted origin, image flags, other sections.
    const std::string path = write_text("atomic.data", "LAMMPS data file via write_data\n\n4 atoms\n2 atom types\n\n"
                                                       "-1 3 xlo xhi\n2 6 ylo yhi\n-0.5 0.5 zlo zhi\n\n"
                                                       "Masses\n\n1 1\n2 1.96\n\n"
                                                       "Atoms # atomic\n\n4 2 0.5 3.5 0 0 0 0\n1 1 1.0 2.5 0 0 0 0\n"
                                                       "3 1 2.0 4.5 0 1 0 0\n2 2 -0.5 5.5 0 0 0 0\n\n"
                                                       "Velocities\n\n1 0 0 0\n2 0 0 0\n3 0 0 0\n4 0 0 0\n");
    const System s = system_from_lammps_data(read_lammps_data(path), path, 4, 1.4);
    std::filesystem::remove(path);
    EXPECT_EQ(s.box.side(), 4.0);
    EXPECT_EQ(s.box.strain(), 0.0);
    // (type, id) order: ids 1, 3 (type 1), 2, 4 (type 2); positions less the origin (-1, 2)
    const std::vector<double> x{2.0, 3.0, 0.5, 1.5}, y{0.5, 2.5, 3.5, 1.5}, d{1.0, 1.0, 1.4, 1.4};
    EXPECT_EQ(s.particles.x, x);
    EXPECT_EQ(s.particles.y, y);
    EXPECT_EQ(s.particles.diameter, d);
}

TEST(LammpsData, TiltBeyondHalfIsTheSameLattice) {
    // xy = 0.75 L: gamma 0.75 wraps to -0.25; lab positions are unchanged modulo the lattice.
    const std::string path =
        write_text("tilt.data", "t\n\n2 atoms\n2 atom types\n0 4 xlo xhi\n0 4 ylo yhi\n-0.5 0.5 zlo zhi\n"
                                "3 0 0 xy xz yz\n\nAtoms # sphere\n\n1 1 1 1 3.5 2 0\n2 2 1.4 1 1 1 0\n");
    const System s = system_from_lammps_data(read_lammps_data(path), path, 2, 1.4);
    std::filesystem::remove(path);
    EXPECT_EQ(s.box.strain(), -0.25);
    // disk 0: lab (3.5, 2): sheared x = 3.5 + 0.25 * 2 = 4.0 -> folds to 0
    EXPECT_DOUBLE_EQ(s.particles.x[0], 0.0);
    EXPECT_DOUBLE_EQ(s.particles.x[1], 1.25);
}

TEST(LammpsData, RefusesWhatIsNotJamsimsMixture) {
    const FinalConfiguration c = configuration(0.1);
    // the two types overlap: a small disk written with the large diameter
    EXPECT_NE(refusal(edited(c, "overlap.data", std::regex("\n1 1 1 1 "), "\n1 1 1.4 1 "))
                  .find("has diameter 1.4: type 1 is the small disk (diameter 1) and type 2 the large one "
                        "(diameter size_ratio = 1.4); each type has one diameter and the two types do not "
                        "overlap"),
              std::string::npos);
    // a third type
    EXPECT_NE(refusal(edited(c, "type3.data", std::regex("\n1 1 1 1 "), "\n1 3 1 1 "))
                  .find("atom 1 has type 3: types 1 (small disks) and 2 (large), at most the header's 2 atom types"),
              std::string::npos);
    // a type past the header's count, named as written (it was clamped to 1000000 or -1)
    EXPECT_NE(refusal(edited(c, "type_big.data", std::regex("\n1 1 1 1 "), "\n1 5000000000 1 1 "))
                  .find("atom 1 has type 5000000000: types 1"),
              std::string::npos);
    EXPECT_NE(refusal(edited(c, "one_type.data", std::regex("\n2 atom types"), "\n1 atom types"))
                  .find("has type 2: types 1 (small disks) and 2 (large), at most the header's 1 atom types"),
              std::string::npos);
    // a header line twice (the last one won), image flags that are not whole numbers
    EXPECT_NE(refusal(edited(c, "twice.data", std::regex("\n2 atom types"), "\n2 atom types\n3 atom types"))
                  .find("a second 'atom types' line in the header"),
              std::string::npos);
    EXPECT_NE(refusal(edited(c, "image.data", std::regex("\n(1 1 1 1 \\S+ \\S+ \\S+)"), "\n$1 1.5 0 0"))
                  .find("atom 1 has image flag '1.5': image flags are whole numbers"),
              std::string::npos);
    // more small than large disks
    EXPECT_NE(refusal(edited(c, "mix.data", std::regex("\n200 2 1.4 1 "), "\n200 1 1 1 "))
                  .find("has 101 atoms of type 1 and 99 of type 2: jamsim's mixture is 50:50 (100 and 100)"),
              std::string::npos);
    // a tilt that is not a simple shear, a cell that is not square
    EXPECT_NE(refusal(edited(c, "xz.data", std::regex(" 0 0 xy xz yz"), " 0.5 0 xy xz yz"))
                  .find("tilt xz = 0.5, yz = 0: a simple shear in the xy plane tilts only xy (xz = yz = 0)"),
              std::string::npos);
    EXPECT_NE(refusal(edited(c, "rect.data", std::regex("\n0 ([0-9.]+) ylo yhi"), "\n0 20 ylo yhi"))
                  .find("jamsim's sheared cell is square (equal sides)"),
              std::string::npos);
    // N of the file against N of the replica
    const std::string n = refusal(edited(c, "n.data", std::regex("test"), "test file"), 256);
    EXPECT_NE(n.find("has 200 atoms: the replica has N = 256 (a file of N atoms)"), std::string::npos) << n;
    // a header that disagrees with the Atoms section, a duplicate id, z != 0
    EXPECT_NE(refusal(edited(c, "count.data", std::regex("200 atoms"), "201 atoms"))
                  .find("the header says 201 atoms, the Atoms section has 200"),
              std::string::npos);
    EXPECT_NE(refusal(edited(c, "dup.data", std::regex("\n2 1 1 1 "), "\n1 1 1 1 ")).find("atom id 1 appears twice"),
              std::string::npos);
    // ids and densities LAMMPS itself refuses
    EXPECT_NE(refusal(edited(c, "neg.data", std::regex("\n2 1 1 1 "), "\n-2 1 1 1 "))
                  .find("atom id -2: atom ids are whole numbers >= 1"),
              std::string::npos);
    EXPECT_NE(refusal(edited(c, "rho.data", std::regex("\n2 1 1 1 "), "\n2 1 1 0 "))
                  .find("atom 2 has density 0: atom_style sphere needs a density > 0"),
              std::string::npos);
    EXPECT_NE(
        refusal(edited(c, "z.data", std::regex(" 0\n"), " 0.25\n")).find("has z = 0.25: a 2D configuration has z = 0"),
        std::string::npos);
    // another atom style, a line with a wrong field count, not a data file at all
    EXPECT_NE(refusal(edited(c, "full.data", std::regex("Atoms # sphere"), "Atoms # full"))
                  .find("Atoms # full: atom_style sphere (id type diameter density x y z) or atomic (id type x y z)"),
              std::string::npos);
    EXPECT_NE(
        refusal(edited(c, "fields.data", std::regex("\n1 1 1 1 ([^ ]+) "), "\n1 1 1 1 "))
            .find("an Atoms line of 6 fields: atom_style sphere has id type diameter density x y z (7, or 10 with "
                  "image flags)"),
        std::string::npos);
    const std::string text = refusal(write_text("notdata.txt", "hello\nworld\n"));
    EXPECT_NE(text.find("is not a LAMMPS data file"), std::string::npos) << text;
    // every message names the file
    EXPECT_NE(text.find("jamsim_test_"), std::string::npos);
}

// A file without line breaks (not text) is refused at its first 4096 characters, not read
// whole (a 300 MB file took 860 MB of memory).
TEST(LammpsData, RefusesALineLongerThanAnyDataFileHas) {
    const std::string path = write_text("one_line.data", "title\n" + std::string(5000, '7') + "\n");
    EXPECT_NE(refusal(path).find("line 2: a line of more than 4096 characters is not allowed"), std::string::npos);
}

// The source's fingerprint (recorded with every replica that starts from it, and compared on
// resume) is the digest of the whole content, read in pieces of 1 MiB: a file of several
// pieces has the digest of its content taken at once.
TEST(LammpsData, FingerprintIsTheDigestOfTheWholeContent) {
    const std::string path = temp_path("fingerprint.data");
    write_lammps_data(path, configuration(0.1, 30000), "test");
    std::ifstream in(path, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(text.size(), std::size_t{1} << 20);
    Digest whole;
    whole.add(std::string_view(text));
    EXPECT_EQ(InitialStates(path).fingerprint(), whole.value());
    std::filesystem::remove(path);
}

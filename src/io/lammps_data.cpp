#include "jamsim/io/lammps_data.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <numeric>
#include <set>
#include <sstream>
#include <string_view>

#include "jamsim/core/parse_number.hpp"

namespace jamsim {

namespace {

/// The first eight bytes of an HDF5 file (superblock at offset 0, as jamsim writes them).
constexpr char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};

/// The shortest of 15 or 17 significant digits that reads back to the same double.
std::string show(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.15g", v);
    if (std::strtod(buf, nullptr) != v) std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/// A double within a few ulps of `near` whose image under `recover` is `target`, so that
/// the reader's arithmetic gives back the writer's value bitwise; `near` when none does.
template <class Recover> double recoverable(double near, double target, Recover recover) {
    if (recover(near) == target) return near;
    double up = near, down = near;
    for (int k = 0; k < 4; ++k) {
        up = std::nextafter(up, std::numeric_limits<double>::infinity());
        if (recover(up) == target) return up;
        down = std::nextafter(down, -std::numeric_limits<double>::infinity());
        if (recover(down) == target) return down;
    }
    return near;
}

std::string_view trim(std::string_view s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return {};
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

std::vector<std::string_view> fields(std::string_view s) {
    std::vector<std::string_view> out;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
        const std::size_t b = i;
        while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
        if (i > b) out.push_back(s.substr(b, i - b));
    }
    return out;
}

bool to_double(std::string_view s, double& out) { return parse_finite(s, out); }
bool to_int(std::string_view s, std::int64_t& out) { return parse_whole_text(s, out); }

bool starts_numeric(std::string_view s) {
    return !s.empty() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '-' || s[0] == '+' || s[0] == '.');
}

}  // namespace

void write_lammps_data(const std::string& path, const FinalConfiguration& c, const std::string& title) {
    std::FILE* raw = std::fopen(path.c_str(), "w");
    if (!raw) throw std::runtime_error("cannot create '" + path + "': " + std::strerror(errno));
    std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(raw, std::fclose);
    std::string head = title;
    std::replace(head.begin(), head.end(), '\n', ' ');
    const std::size_t n = c.x.size();
    const double L = c.box_side, gamma = c.box_strain;
    // xy such that the reader's xy / L is γ bitwise (where a double does it).
    const double xy = recoverable(gamma * L, gamma, [L](double v) { return v / L; });
    bool ok = std::fprintf(out.get(), "%s\n\n%zu atoms\n2 atom types\n\n", head.c_str(), n) > 0;
    ok = ok && std::fprintf(out.get(), "0 %.17g xlo xhi\n0 %.17g ylo yhi\n-0.5 0.5 zlo zhi\n%.17g 0 0 xy xz yz\n\n", L,
                            L, xy) > 0;
    ok = ok && std::fprintf(out.get(), "Atoms # sphere\n\n") > 0;
    const double small = n > 0 ? *std::min_element(c.diameter.begin(), c.diameter.end()) : 1.0;
    for (std::size_t i = 0; i < n && ok; ++i) {
        const double shift = gamma * c.y[i];  // the reader subtracts exactly this
        const double lab_x = recoverable(c.x[i] + shift, c.x[i], [shift](double v) { return v - shift; });
        ok = std::fprintf(out.get(), "%zu %d %s 1 %.17g %.17g 0\n", i + 1, c.diameter[i] > small ? 2 : 1,
                          show(c.diameter[i]).c_str(), lab_x, c.y[i]) > 0;
    }
    // errno of the first failure: fprintf, the final flush or the close (a full disk shows here).
    ok = ok && std::fflush(out.get()) == 0 && !std::ferror(out.get());
    const int write_error = errno;
    if (!ok) throw std::runtime_error("writing '" + path + "' failed: " + std::strerror(write_error));
    if (std::fclose(out.release()) != 0)
        throw std::runtime_error("writing '" + path + "' failed: " + std::strerror(errno));
}

namespace {
/// The longest line read from a data file: its lines hold a few numbers (a file without line
/// breaks, not text, is refused at this length rather than read whole).
constexpr std::size_t kLongestLine = 4096;

/// The next line of `in` (line `line` of the file `path`) into `raw`, without its line break;
/// false at the end of the file.
bool next_line(std::istream& in, std::string& raw, const std::string& path, std::size_t line) {
    raw.clear();
    std::streambuf& buf = *in.rdbuf();
    for (int c = buf.sbumpc(); c != std::char_traits<char>::eof(); c = buf.sbumpc()) {
        if (c == '\n') return true;
        if (raw.size() == kLongestLine)
            throw LammpsDataError("'" + path + "' line " + std::to_string(line) + ": a line of more than " +
                                  std::to_string(kLongestLine) +
                                  " characters is not allowed: a data file's lines hold a few numbers (is it a "
                                  "text file?)");
        raw.push_back(static_cast<char>(c));
    }
    return !raw.empty();
}
}  // namespace

namespace {

/// Reads a LAMMPS data file line by line into LammpsData: the header, then its sections
/// (only Atoms is kept). Each method takes one line; `where` names the file and the line.
class DataFileReader {
  public:
    explicit DataFileReader(const std::string& path) : path_(path) {}

    void read_line(std::string_view full, std::size_t line_no) {
        line_no_ = line_no;
        const auto hash = full.find('#');
        const std::string_view text = trim(full.substr(0, hash));
        if (text.empty()) return;
        const auto f = fields(text);
        if (!starts_numeric(f[0]))
            read_section_keyword(full, text, hash);
        else if (section_.empty())
            read_header_line(text, f);
        else if (section_ == "Atoms")  // Masses, Velocities, Pair Coeffs, ...: not needed
            read_atom_line(text, f);
    }

    LammpsData finish() {
        if (!have_atoms_ || !have_types_ || !have_x_ || !have_y_)
            throw LammpsDataError("'" + path_ +
                                  "' is not a LAMMPS data file: its header needs 'N atoms', 'N atom types', "
                                  "'xlo xhi' and 'ylo yhi'");
        if (!sections_seen_.count("Atoms")) throw LammpsDataError("'" + path_ + "' has no Atoms section");
        if (static_cast<std::int64_t>(d_.id.size()) != d_.atoms)
            throw LammpsDataError("'" + path_ + "': the header says " + std::to_string(d_.atoms) +
                                  " atoms, the Atoms section has " + std::to_string(d_.id.size()));
        return std::move(d_);
    }

  private:
    std::string where() const { return "'" + path_ + "' line " + std::to_string(line_no_) + ": "; }

    void read_section_keyword(std::string_view full, std::string_view text, std::size_t hash) {
        // ... unless it is a header line with a value that is not a number ("nan 0 0 xy xz
        // yz" was taken for a section, and the tilt for 0).
        for (const char* header : {" xy xz yz", " xlo xhi", " ylo yhi", " zlo zhi", " atoms", " atom types"})
            if (section_.empty() && text.size() > std::strlen(header) && text.ends_with(header))
                throw LammpsDataError(where() + "'" + std::string(text) + "': finite numbers before '" +
                                      std::string(header + 1) + "'");
        section_ = std::string(text);
        if (sections_seen_.count(section_)) throw LammpsDataError(where() + "a second '" + section_ + "' section");
        sections_seen_.insert(section_);
        if (section_ == "Atoms" && hash != std::string_view::npos)
            style_hint_ = std::string(trim(full.substr(hash + 1)));
    }

    void read_header_line(std::string_view text, const std::vector<std::string_view>& f) {
        const auto keyword = [&](std::size_t k) {
            std::string s;
            for (std::size_t i = k; i < f.size(); ++i) {
                if (i > k) s.push_back(' ');
                s.append(f[i]);
            }
            return s;
        };
        // One line of each (LAMMPS would take the last of two silently).
        for (const std::string& said : {keyword(1), keyword(2), keyword(3)})
            if (said == "atoms" || said == "atom types" || said == "xlo xhi" || said == "ylo yhi" ||
                said == "zlo zhi" || said == "xy xz yz") {
                if (!header_seen_.insert(said).second)
                    throw LammpsDataError(where() + "a second '" + said + "' line in the header");
                break;
            }
        std::int64_t count = 0;
        if (f.size() >= 2 && keyword(1) == "atoms") {
            if (!to_int(f[0], count) || count < 0)
                throw LammpsDataError(where() + "atoms = " + std::string(f[0]) + ": a count >= 0");
            d_.atoms = count;
            have_atoms_ = true;
        } else if (f.size() >= 3 && keyword(1) == "atom types") {
            if (!to_int(f[0], count) || count < 1)
                throw LammpsDataError(where() + "atom types = " + std::string(f[0]) + ": a count >= 1");
            d_.atom_types = count;
            have_types_ = true;
        } else if (f.size() == 4 && (keyword(2) == "xlo xhi" || keyword(2) == "ylo yhi" || keyword(2) == "zlo zhi")) {
            double lo = 0, hi = 0;
            if (!to_double(f[0], lo) || !to_double(f[1], hi) || !(hi > lo))
                throw LammpsDataError(where() + "'" + std::string(text) + "': two numbers lo < hi");
            if (f[2] == "xlo") {
                d_.xlo = lo;
                d_.xhi = hi;
                have_x_ = true;
            } else if (f[2] == "ylo") {
                d_.ylo = lo;
                d_.yhi = hi;
                have_y_ = true;
            } else {
                d_.zlo = lo;
                d_.zhi = hi;
            }
        } else if (f.size() == 6 && keyword(3) == "xy xz yz") {
            if (!to_double(f[0], d_.xy) || !to_double(f[1], d_.xz) || !to_double(f[2], d_.yz))
                throw LammpsDataError(where() + "'" + std::string(text) + "': three numbers");
        }
        // other header lines (bonds, extra/atom, ellipsoids, ...) say nothing about disks
    }

    /// atom_style from the section's comment ("Atoms # sphere"), else from the first line's
    /// field count.
    void choose_atom_style(std::size_t field_count) {
        const std::string hint = fields(style_hint_).empty() ? "" : std::string(fields(style_hint_)[0]);
        if (hint == "sphere" || hint == "atomic")
            d_.atom_style = hint;
        else if (!hint.empty())
            throw LammpsDataError(where() + "Atoms # " + hint +
                                  ": atom_style sphere (id type diameter density x y z) or atomic (id type x y z)");
        else if (field_count == 5 || field_count == 8)
            d_.atom_style = "atomic";
        else
            d_.atom_style = "sphere";
    }

    void read_atom_line(std::string_view text, const std::vector<std::string_view>& f) {
        if (d_.atom_style.empty()) choose_atom_style(f.size());
        const bool sphere = d_.atom_style == "sphere";
        const std::size_t columns = sphere ? 7 : 5;
        if (f.size() != columns && f.size() != columns + 3)
            throw LammpsDataError(
                where() + "an Atoms line of " + std::to_string(f.size()) + " fields: atom_style " + d_.atom_style +
                " has " + (sphere ? "id type diameter density x y z" : "id type x y z") + " (" +
                std::to_string(columns) + ", or " + std::to_string(columns + 3) + " with image flags)");
        std::int64_t id = 0, type = 0;
        double diameter = 0, density = 0, x = 0, y = 0, z = 0;
        const std::size_t p = sphere ? 4 : 2;
        if (!to_int(f[0], id) || !to_int(f[1], type) ||
            (sphere && (!to_double(f[2], diameter) || !to_double(f[3], density))) || !to_double(f[p], x) ||
            !to_double(f[p + 1], y) || !to_double(f[p + 2], z))
            throw LammpsDataError(where() + "'" + std::string(text) + "': integer id and type, finite numbers");
        // As LAMMPS's own reader demands ("Invalid atom ID", "Invalid density in Atoms section").
        if (id < 1)
            throw LammpsDataError(where() + "atom id " + std::string(f[0]) + ": atom ids are whole numbers >= 1");
        if (sphere && !(density > 0))
            throw LammpsDataError(where() + "atom " + std::string(f[0]) + " has density " + std::string(f[3]) +
                                  ": atom_style sphere needs a density > 0");
        // LAMMPS: "Invalid atom type"; jamsim's disks are of two types.
        if (type < 1 || (have_types_ && type > d_.atom_types) || type > 2)
            throw LammpsDataError(where() + "atom " + std::string(f[0]) + " has type " + std::string(f[1]) +
                                  ": types 1 (small disks) and 2 (large), at most the header's " +
                                  std::to_string(d_.atom_types) + " atom types");
        for (std::size_t k = columns; k < f.size(); ++k)  // image flags: whole numbers
            if (std::int64_t image = 0; !to_int(f[k], image))
                throw LammpsDataError(where() + "atom " + std::string(f[0]) + " has image flag '" + std::string(f[k]) +
                                      "': image flags are whole numbers");
        d_.id.push_back(id);
        d_.type.push_back(static_cast<int>(type));
        if (sphere) d_.diameter.push_back(diameter);
        d_.x.push_back(x);
        d_.y.push_back(y);
        d_.z.push_back(z);
    }

    const std::string& path_;
    LammpsData d_;
    std::size_t line_no_ = 0;
    bool have_x_ = false, have_y_ = false, have_atoms_ = false, have_types_ = false;
    std::string section_;     ///< the section being read; empty in the header
    std::string style_hint_;  ///< the Atoms line's comment ("sphere", "atomic")
    std::set<std::string> sections_seen_;
    std::set<std::string> header_seen_;  ///< the header lines read (atoms, xlo xhi, ...)
};

}  // namespace

LammpsData read_lammps_data(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw LammpsDataError("'" + path + "' cannot be read");
    DataFileReader reader(path);
    std::string raw;
    std::size_t line_no = 1;
    next_line(in, raw, path, line_no);  // the title
    while (next_line(in, raw, path, line_no + 1)) reader.read_line(raw, ++line_no);
    if (in.bad()) throw LammpsDataError("'" + path + "' cannot be read");
    return reader.finish();
}

System system_from_lammps_data(const LammpsData& d, const std::string& path, std::int64_t n, double size_ratio) {
    const std::string file = "'" + path + "'";
    if (d.atoms != n)
        throw LammpsDataError(file + " has " + std::to_string(d.atoms) +
                              " atoms: the replica has N = " + std::to_string(n) + " (a file of N atoms)");
    {
        std::vector<std::int64_t> ids = d.id;
        std::sort(ids.begin(), ids.end());
        const auto dup = std::adjacent_find(ids.begin(), ids.end());
        if (dup != ids.end())
            throw LammpsDataError(file + ": atom id " + std::to_string(*dup) + " appears twice (ids are unique)");
    }
    {  // two disks at one spot: an infinite-looking force the first step could only call unstable
        std::vector<std::size_t> at(d.id.size());
        std::iota(at.begin(), at.end(), std::size_t{0});
        std::sort(at.begin(), at.end(),
                  [&](std::size_t a, std::size_t b) { return d.x[a] != d.x[b] ? d.x[a] < d.x[b] : d.y[a] < d.y[b]; });
        for (std::size_t k = 1; k < at.size(); ++k)
            if (d.x[at[k]] == d.x[at[k - 1]] && d.y[at[k]] == d.y[at[k - 1]])
                throw LammpsDataError(file + ": atoms " + std::to_string(d.id[at[k - 1]]) + " and " +
                                      std::to_string(d.id[at[k]]) + " are at the same position (" + show(d.x[at[k]]) +
                                      ", " + show(d.y[at[k]]) + "): every disk needs a place of its own");
    }
    std::int64_t small_count = 0;
    for (std::size_t i = 0; i < d.id.size(); ++i) {
        // (types are 1 or 2: read_lammps_data refuses others)
        if (d.type[i] == 1) ++small_count;
        if (!d.diameter.empty()) {
            const double expected = d.type[i] == 1 ? 1.0 : size_ratio;
            if (!(std::abs(d.diameter[i] - expected) <= 1e-12 * expected))
                throw LammpsDataError(file + ": atom " + std::to_string(d.id[i]) + " of type " +
                                      std::to_string(d.type[i]) + " has diameter " + show(d.diameter[i]) +
                                      ": type 1 is the small disk (diameter 1) and type 2 the large one (diameter "
                                      "size_ratio = " +
                                      show(size_ratio) +
                                      "); each type has one diameter and the two types do not overlap");
        }
    }
    if (size_ratio != 1.0 && small_count * 2 != n)
        throw LammpsDataError(file + " has " + std::to_string(small_count) + " atoms of type 1 and " +
                              std::to_string(n - small_count) + " of type 2: jamsim's mixture is 50:50 (" +
                              std::to_string(n / 2) + " and " + std::to_string(n / 2) + ")");
    if (d.xz != 0.0 || d.yz != 0.0)
        throw LammpsDataError(file + ": tilt xz = " + show(d.xz) + ", yz = " + show(d.yz) +
                              ": a simple shear in the xy plane tilts only xy (xz = yz = 0)");
    const double lx = d.xhi - d.xlo, ly = d.yhi - d.ylo;
    if (!(std::abs(lx - ly) <= 1e-12 * ly))
        throw LammpsDataError(file + ": the cell is " + show(lx) + " x " + show(ly) +
                              " (xhi - xlo, yhi - ylo): jamsim's sheared cell is square (equal sides)");
    for (std::size_t i = 0; i < d.z.size(); ++i)
        if (d.z[i] != 0.0)
            throw LammpsDataError(file + ": atom " + std::to_string(d.id[i]) + " has z = " + show(d.z[i]) +
                                  ": a 2D configuration has z = 0");
    const double side = ly;
    // Folding the tilt into [-L/2, L/2) and the atoms into the cell loses a bit of precision
    // for each doubling beyond the cell: at most 20 of them (a tilt of 1e308 became 0).
    constexpr double kMostCells = 1048576.0;
    if (!(std::abs(d.xy) <= kMostCells * side))
        throw LammpsDataError(file + ": tilt xy = " + show(d.xy) + " is not allowed: |xy| <= 2^20 (xhi - xlo) = " +
                              show(kMostCells * side) + " (LAMMPS keeps it within half of xhi - xlo)");
    for (std::size_t i = 0; i < d.x.size(); ++i)
        if (!(std::abs(d.x[i] - d.xlo) <= kMostCells * side && std::abs(d.y[i] - d.ylo) <= kMostCells * side))
            throw LammpsDataError(file + ": atom " + std::to_string(d.id[i]) + " at (" + show(d.x[i]) + ", " +
                                  show(d.y[i]) + ") is not allowed: within 2^20 cell sides of the cell");
    double gamma = d.xy / side;
    gamma -= std::floor(gamma + 0.5);  // into [-1/2, 1/2): the same lattice (xy shifted by whole xprd)
    std::vector<std::size_t> order(d.id.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return d.type[a] != d.type[b] ? d.type[a] < d.type[b] : d.id[a] < d.id[b];
    });
    const Box box(side, gamma);
    Particles q;
    q.resize(static_cast<std::size_t>(n));
    for (std::size_t k = 0; k < order.size(); ++k) {
        const std::size_t i = order[k];
        const double ys = d.y[i] - d.ylo;
        double xs = (d.x[i] - d.xlo) - box.strain() * ys;
        double yw = ys;
        box.wrap_into_cell(xs, yw);
        q.x[k] = xs;
        q.y[k] = yw;
        q.diameter[k] = d.type[i] == 1 ? 1.0 : size_ratio;
        q.tag[k] = static_cast<std::int32_t>(k);
    }
    return System{std::move(q), box};
}

bool is_hdf5_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw LammpsDataError("'" + path + "' does not exist");
    if (std::filesystem::is_directory(path, ec)) throw LammpsDataError("'" + path + "' is a directory");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw LammpsDataError("'" + path + "' cannot be read");
    char head[8] = {};
    in.read(head, sizeof head);
    return in.gcount() == 8 && std::equal(head, head + 8, kSignature);
}

}  // namespace jamsim

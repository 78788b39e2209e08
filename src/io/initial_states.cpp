#include "jamsim/io/initial_states.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <utility>
#include <vector>

#include "jamsim/core/digest.hpp"

#include "jamsim/io/hdf5.hpp"
#include "jamsim/io/stored_replicas.hpp"

namespace jamsim {

namespace {
std::string show(double v) { return show_value(v); }
}  // namespace

namespace {
/// The cell scaled affinely to phi (positions and side) when it is at another packing
/// fraction (more than round-off away).
void scale_to_phi(Particles& q, double& side, double phi) {
    const double target = box_side_for(q, phi);
    if (std::abs(target / side - 1.0) > 1e-12) {
        const double s = target / side;
        for (std::size_t i = 0; i < q.size(); ++i) {
            q.x[i] *= s;
            q.y[i] *= s;
        }
        side = target;
    }
}
/// Digest::add of the file's whole content, read in pieces (a data file of 10^6 disks is
/// about 60 MB).
std::uint64_t file_digest(const std::string& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    if (ec || !in) throw LammpsDataError("'" + path + "' cannot be read");
    Digest d;
    d.add(static_cast<std::uint64_t>(size));
    std::vector<char> piece(std::size_t{1} << 20);
    std::uintmax_t read = 0;
    while (in) {
        in.read(piece.data(), static_cast<std::streamsize>(piece.size()));
        const auto got = static_cast<std::size_t>(in.gcount());
        d.add_bytes(std::string_view(piece.data(), got));
        read += got;
    }
    if (read != size) throw LammpsDataError("'" + path + "' changed while it was read");
    return d.value();
}

}  // namespace

InitialStates::InitialStates(const std::string& source) : source_(source) {
    const std::string allowed = "a jamsim campaign archive or a LAMMPS data file (";
    try {
        if (!is_hdf5_file(source)) {
            lammps_ = read_lammps_data(source);
            fingerprint_ = file_digest(source);  // its content is what starts every replica
            return;
        }
    } catch (const LammpsDataError& e) { throw InitialStateError(source, allowed + e.what() + ")", true); }
    h5::quiet_errors();
    try {
        const h5::Handle f = h5::open_unlocked_readonly(source);
        status_ = h5::read_all<std::int8_t>(f.get(), "/replicas/status", H5T_NATIVE_INT8);
        n_ = h5::read_dataset(f.get(), "/replicas/N");
        phi_ = h5::read_dataset(f.get(), "/replicas/phi");
        seed_ = h5::read_dataset(f.get(), "/replicas/seed");
        Digest d;  // the source campaign's identity: a longer or grown campaign is another source
        d.add(std::string_view(h5::read_string_attribute(f.get(), "spec_fingerprint")));
        fingerprint_ = d.value();
        if (h5::exists(f.get(), "/replicas/size_ratio"))
            size_ratio_ = h5::read_dataset(f.get(), "/replicas/size_ratio");
    } catch (const h5::Error& e) { throw InitialStateError(source, allowed + e.what() + ")", true); }
}

std::int64_t InitialStates::match(const ReplicaParams& p, std::int64_t id) const {
    const std::int64_t k = find(p, id);
    const auto at = static_cast<std::size_t>(k);
    if (!lammps_ && at < size_ratio_.size() && std::isfinite(size_ratio_[at]) && size_ratio_[at] != p.size_ratio)
        throw InitialStateError(source_,
                                "replica " + std::to_string(k) + " has size_ratio = " + show(size_ratio_[at]) +
                                    ", replica " + std::to_string(id) + " here size_ratio = " + show(p.size_ratio) +
                                    ": its disks would have other diameters (start from a source of the same mixture)");
    return k;
}

std::int64_t InitialStates::find(const ReplicaParams& p, std::int64_t id) const {
    if (lammps_) {
        try {
            (void)system_from_lammps_data(*lammps_, source_, p.n, p.size_ratio);
        } catch (const LammpsDataError& e) { throw InitialStateError(source_, e.what()); }
        return 0;
    }
    if (p.initial_match == "id") {
        if (id < 0 || id >= static_cast<std::int64_t>(status_.size()))
            throw InitialStateError(source_, "no replica " + std::to_string(id) + " (it has " +
                                                 std::to_string(status_.size()) + ")");
        const auto k = static_cast<std::size_t>(id);
        if (status_[k] != 2) throw InitialStateError(source_, "replica " + std::to_string(id) + " is not finished");
        if (n_[k] != static_cast<double>(p.n))
            throw InitialStateError(source_, "replica " + std::to_string(id) + " has N = " + show(n_[k]) +
                                                 ", replica " + std::to_string(id) +
                                                 " here N = " + std::to_string(p.n));
        return id;
    }
    std::int64_t found = -1;
    for (std::size_t k = 0; k < status_.size(); ++k) {
        if (n_[k] != static_cast<double>(p.n) || phi_[k] != p.phi || seed_[k] != static_cast<double>(p.seed)) continue;
        if (found >= 0)
            throw InitialStateError(source_, "replicas " + std::to_string(found) + " and " + std::to_string(k) +
                                                 " both have N = " + std::to_string(p.n) + ", phi = " + show(p.phi) +
                                                 ", seed = " + std::to_string(p.seed) + ": use initial_match = \"id\"");
        found = static_cast<std::int64_t>(k);
    }
    if (found < 0 || status_[static_cast<std::size_t>(found)] != 2)
        throw InitialStateError(source_, "no finished replica with N = " + std::to_string(p.n) +
                                             ", phi = " + show(p.phi) + ", seed = " + std::to_string(p.seed));
    return found;
}

System InitialStates::load(const ReplicaParams& p, std::int64_t id) const {
    if (lammps_) {
        try {
            System sys = system_from_lammps_data(*lammps_, source_, p.n, p.size_ratio);
            double side = sys.box.side();
            scale_to_phi(sys.particles, side, p.phi);
            return System{std::move(sys.particles), Box(side, sys.box.strain())};
        } catch (const LammpsDataError& e) { throw InitialStateError(source_, e.what()); }
    }
    const auto k = static_cast<hsize_t>(match(p, id));
    const auto n = static_cast<hsize_t>(p.n);
    h5::quiet_errors();
    try {
        const h5::Handle f = h5::open_unlocked_readonly(source_);
        FinalConfiguration c =
            read_final_configuration(f.get(), static_cast<std::int64_t>(k), static_cast<std::int64_t>(n));
        if (const std::string why = damaged_final(c); !why.empty())
            throw InitialStateError(source_, "replica " + std::to_string(k) + "'s final state " + why +
                                                 " (a hand-edited or damaged archive?)");
        Particles q;
        q.resize(n);
        q.x = std::move(c.x);
        q.y = std::move(c.y);
        q.diameter = std::move(c.diameter);
        double side = c.box_side;
        const double strain = c.box_strain;
        for (std::size_t i = 0; i < q.size(); ++i) {
            q.tag[i] = static_cast<std::int32_t>(i);
            const double expected = (i < q.size() / 2 || p.size_ratio == 1.0) ? 1.0 : p.size_ratio;
            if (q.diameter[i] != expected)
                throw InitialStateError(source_, "replica " + std::to_string(k) + " has disk " + std::to_string(i) +
                                                     " of diameter " + show(q.diameter[i]) +
                                                     ", this campaign's size_ratio = " + show(p.size_ratio) +
                                                     " gives " + show(expected));
        }
        scale_to_phi(q, side, p.phi);  // another phi: scale the cell affinely
        return System{std::move(q), Box(side, strain)};
    } catch (const h5::Error& e) {
        throw InitialStateError(source_, "replica " + std::to_string(k) + " cannot be read: " + e.what());
    }
}

}  // namespace jamsim

namespace jamsim {

std::uint64_t InitialStates::digest(const System& system) {
    Digest d;
    d.add(system.box.side());
    d.add(system.box.strain());
    d.add(system.particles.x);
    d.add(system.particles.y);
    d.add(system.particles.diameter);
    return d.value();
}

std::string InitialStates::changed_since(const std::vector<ReplicaParams>& replicas,
                                         const std::vector<std::uint64_t>& recorded_source,
                                         const std::vector<std::uint64_t>& recorded_state) const {
    std::string changed;
    int listed = 0, count = 0;
    for (std::size_t id = 0; id < replicas.size() && id < recorded_source.size() && id < recorded_state.size(); ++id) {
        if (recorded_source[id] == 0 || recorded_source[id] == fingerprint_)
            continue;  // not started, or the same source
        std::uint64_t now = 0;
        try {
            now = digest(load(replicas[id], static_cast<std::int64_t>(id)));
        } catch (const InitialStateError&) {}
        if (now == recorded_state[id]) continue;  // the source changed elsewhere
        ++count;
        if (listed++ < 5) changed += (changed.empty() ? "" : ", ") + std::to_string(id);
    }
    if (count == 0) return "";
    return "[run] initial = \"" + source_ +
           "\" has changed since this archive's replicas started from it: the state that " + "started replica" +
           (count > 1 ? "s " : " ") + changed +
           (count > listed ? " and " + std::to_string(count - listed) + " more" : "") +
           " is not in it any more (the source was extended, rerun or replaced); running on would mix starting states "
           "in " +
           "one campaign: restore the source, or run this campaign into a new output";
}

}  // namespace jamsim

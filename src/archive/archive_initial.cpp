// What each replica of a campaign with [run] initial started from: the source's fingerprint
// and the starting state's digest (/replicas/initial_source, /replicas/initial_state), so
// that a source changed between runs of the campaign is refused instead of mixed in.
#include "jamsim/archive/archive.hpp"
#include "archive_detail.hpp"

namespace jamsim {

using archive_detail::write_block;

void create_initial_columns(hid_t file, const CampaignSpec& spec) {
    if (spec.replicas.empty() || spec.replicas.front().initial.empty()) return;
    const auto replicas = static_cast<hsize_t>(spec.replicas.size());
    const std::uint64_t none = 0;
    h5::create_filled_dataset(file, "/replicas/initial_source", H5T_NATIVE_UINT64, {replicas}, &none, "1",
                              "fingerprint of the [run] initial source when the replica started from it "
                              "(its campaign's spec_fingerprint or the data file's content; 0: not started)");
    h5::create_filled_dataset(file, "/replicas/initial_state", H5T_NATIVE_UINT64, {replicas}, &none, "1",
                              "digest of the state the replica started from (box, positions, diameters; "
                              "0: not started)");
}

void Archive::record_initial(std::int64_t replica, std::uint64_t source, std::uint64_t state) {
    if (!h5::exists(file_.get(), "/replicas/initial_source")) return;  // an older archive
    const auto r = static_cast<hsize_t>(replica);
    write_block(file_.get(), "/replicas/initial_state", H5T_NATIVE_UINT64, {r}, {1}, &state);
    write_block(file_.get(), "/replicas/initial_source", H5T_NATIVE_UINT64, {r}, {1}, &source);
}

InitialRecords read_initial_records(const std::string& path) {
    h5::quiet_errors();
    InitialRecords out;
    const h5::Handle f = h5::open_unlocked_readonly(path);
    if (!h5::exists(f.get(), "/replicas/initial_source")) return out;
    out.source = h5::read_all<std::uint64_t>(f.get(), "/replicas/initial_source", H5T_NATIVE_UINT64);
    out.state = h5::read_all<std::uint64_t>(f.get(), "/replicas/initial_state", H5T_NATIVE_UINT64);
    return out;
}

}  // namespace jamsim

#pragma once
// What the archive's source files share (archive.cpp, archive_extend.cpp, archive_summary.cpp).
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "jamsim/io/hdf5.hpp"
#include "jamsim/spec/campaign_spec.hpp"

namespace jamsim::archive_detail {

inline constexpr std::size_t kReasonLength = 200;  // bytes of /replicas/failure_reason
/// The root's time stamps (Archive::stamp), made at creation as fixed-length text of
/// kStampBytes bytes ("2026-11-29T09:01:35Z" is 20) and written over where they stand.
inline constexpr const char* kStampAttributes[] = {"run_started", "run_finished", "merged", "extended", "grown"};
inline constexpr std::size_t kStampBytes = 32;

/// A numeric per-replica column of /replicas: a used parameter, or a derived figure.
struct Column {
    std::string name, units, description;
    std::function<double(const ReplicaParams&)> value;
};

/// A dataset's shape and HDF5 type class (H5T_INTEGER, H5T_FLOAT, H5T_STRING, ...)
/// (archive_file_check.cpp).
struct DatasetForm {
    std::vector<hsize_t> dims;
    H5T_class_t type;
};
DatasetForm dataset_form(hid_t file, const std::string& path);
/// "a scalar", "64 entries", "2 x 11".
std::string shape_text(const std::vector<hsize_t>& dims);

/// The campaign stored in an archive (its spec_text, a copy of `spec_path`), parsed; a
/// SpecError "its stored campaign (attribute spec_text, a copy of '...') does not parse (line
/// 3:6: ...)" when it does not: the archive is damaged, not the campaign file it names.
CampaignSpec parse_stored_campaign(const std::string& text, const std::string& spec_path);

/// The parameter columns of a campaign: every numeric parameter that its model uses for at
/// least one replica (NaN for replicas that do not use it), then the derived figures
/// (archive_create.cpp).
std::vector<Column> parameter_columns(const CampaignSpec& spec);

/// "" when the archive `f` is the one its stored campaign (spec_text) makes: that campaign
/// parses and has the archive's fingerprint, its text parameters are the root's attributes,
/// its per-replica values are the parameter columns, and every dataset a run writes is there
/// with the class and shape the campaign gives it; else the first difference
/// (archive_campaign_check.cpp). A hand-edited phi was exported under that label, a dataset
/// retyped by hand made a resume fail half-way through its writes.
std::string campaign_mismatch(hid_t f);

/// Independent write of a block of an archive dataset (the rank that runs a replica).
inline void write_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                        std::vector<hsize_t> count, const void* data) {
    const h5::Handle dxpl = h5::independent_transfer();
    h5::write_block(file, path, memtype, std::move(start), std::move(count), data, dxpl.get());
}

}  // namespace jamsim::archive_detail

#pragma once
// What the archive's source files share (archive.cpp, archive_extend.cpp, archive_summary.cpp).
#include <string>
#include <utility>
#include <vector>

#include "jamsim/io/hdf5.hpp"

namespace jamsim::archive_detail {

inline constexpr std::size_t kReasonLength = 200;  // bytes of /replicas/failure_reason
/// The root's time stamps (Archive::stamp), made at creation as fixed-length text of
/// kStampBytes bytes ("2026-11-29T09:01:35Z" is 20) and written over where they stand.
inline constexpr const char* kStampAttributes[] = {"run_started", "run_finished", "merged", "extended", "grown"};
inline constexpr std::size_t kStampBytes = 32;

/// Independent write of a block of an archive dataset (the rank that runs a replica).
inline void write_block(hid_t file, const std::string& path, hid_t memtype, std::vector<hsize_t> start,
                        std::vector<hsize_t> count, const void* data) {
    const h5::Handle dxpl = h5::independent_transfer();
    h5::write_block(file, path, memtype, std::move(start), std::move(count), data, dxpl.get());
}

}  // namespace jamsim::archive_detail

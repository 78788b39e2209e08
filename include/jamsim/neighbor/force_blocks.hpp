#pragma once
// The fixed decomposition of a neighbour list into blocks of disks, on which the force loop
// runs (force/pair_forces.hpp). It depends on the list alone (the disk count and the
// entries), never on the number of threads, so the forces come out the same bits however
// many threads share the blocks.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace jamsim {

/// Disks 0 .. N−1 in blocks of `size` consecutive indices; block b owns the list entries of
/// its disks (a contiguous range of the list, which is grouped by owner). The force loop
/// adds each entry's force into its owner and, when the neighbour lies in the same block,
/// into the neighbour too; when it does not, it writes the neighbour's share into a halo slot
/// instead, and a second pass adds the halo slots into their disks: for each disk, the slots
/// of source blocks 0, 1, 2, ... in turn, each block's in list order. So a disk's force is
/// (its block's entries, in list order) + (halo slots, in (source block, list) order), on
/// any number of threads. Particles are sorted by cell (spatial_order), so neighbours lie
/// mostly in the same block: a few per cent of the entries need a halo slot.
struct ForceBlocks {
    /// Disks per block for N disks: one block up to 4096 disks (then the loop is the plain
    /// one-pass scatter), else 32 blocks of at least 4096 disks (enough to share among
    /// threads; few enough that the halo stays a few per cent of the entries).
    static std::size_t block_size(std::size_t n) {
        constexpr std::size_t kMinimum = 4096, kBlocks = 32;
        return std::max(kMinimum, (n + kBlocks - 1) / kBlocks);
    }

    std::size_t size = 0;   ///< disks per block (the last may hold fewer)
    std::size_t count = 0;  ///< blocks
    std::vector<std::int32_t> entry_first;  ///< [count + 1]: block b owns entries [entry_first[b], entry_first[b+1])
    /// [entries]: where entry k's neighbour share goes: the neighbour j (≥ 0) when it lies in
    /// the owner's block, else ~s (< 0) for halo slot s.
    std::vector<std::int32_t> target;
    /// [count·count + 1]: the halo slots written by block b for disks of block c are
    /// [halo_first[b·count + c], halo_first[b·count + c + 1]), in list order.
    std::vector<std::int32_t> halo_first;
    std::vector<std::int32_t> halo_disk;  ///< [slots]: the disk each halo slot belongs to

    std::size_t block_of(std::int32_t disk) const { return static_cast<std::size_t>(disk) / size; }
    std::size_t halo_slots() const { return halo_disk.size(); }

    /// Decompose the list with CSR offsets `first` (shape [N + 1]) and `neighbor` (entries).
    void build(std::span<const std::int32_t> first, std::span<const std::int32_t> neighbor);
};

} // namespace jamsim

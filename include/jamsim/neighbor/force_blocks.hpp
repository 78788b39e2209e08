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
/// into the neighbour too; when it does not, it writes the neighbour's share into the block's
/// next halo slot instead, and a second pass adds the halo slots into their disks: for each
/// disk, the slots of source blocks 0, 1, 2, ... in turn, each block's in list order. So a disk's force is
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
    /// Blocks for N disks (at least 1): more threads than this gain nothing in the pair loop.
    static std::size_t block_count(std::size_t n) { return n == 0 ? 1 : (n + block_size(n) - 1) / block_size(n); }

    std::size_t size = 0;                   ///< disks per block (the last may hold fewer)
    std::size_t count = 0;                  ///< blocks
    std::vector<std::int32_t> entry_first;  ///< [count + 1]: block b owns entries [entry_first[b], entry_first[b+1])
    /// [count + 1]: block b's halo slots are [slot_first[b], slot_first[b+1]), one per entry
    /// whose neighbour lies in another block, in list order (the force loop counts them as it
    /// goes: no per-entry array to stream).
    std::vector<std::int32_t> slot_first;
    std::vector<std::int32_t> halo_disk;  ///< [slots]: the disk (neighbour) each slot belongs to
    /// The slots by (source block b, target block c): by_target[by_target_first[b·count + c]
    /// .. by_target_first[b·count + c + 1]) are b's slots for disks of block c, in list order.
    std::vector<std::int32_t> by_target_first, by_target;

    std::size_t block_of(std::int32_t disk) const { return static_cast<std::size_t>(disk) / size; }
    std::size_t halo_slots() const { return halo_disk.size(); }
    std::size_t first_disk(std::size_t b) const { return b * size; }

    /// Decompose the list with CSR offsets `first` (shape [N + 1]) and `neighbor` (entries).
    void build(std::span<const std::int32_t> first, std::span<const std::int32_t> neighbor);
};

}  // namespace jamsim

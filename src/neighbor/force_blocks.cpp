#include "jamsim/neighbor/force_blocks.hpp"

#include <algorithm>

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

void ForceBlocks::build(std::span<const std::int32_t> first, std::span<const std::int32_t> neighbor) {
    const std::size_t n = first.empty() ? 0 : first.size() - 1;
    size = block_size(n);
    count = std::max<std::size_t>(1, (n + size - 1) / size);
    entry_first.resize(count + 1);
    for (std::size_t b = 0; b <= count; ++b) entry_first[b] = first[std::min(b * size, n)];
    // Halo entries per (source block, target block).
    std::vector<std::int32_t> per_pair(count * count, 0);
    parallel_for_blocks(count, [&](std::size_t b) {
        std::int32_t* row = per_pair.data() + b * count;
        for (auto k = static_cast<std::size_t>(entry_first[b]); k < static_cast<std::size_t>(entry_first[b + 1]); ++k) {
            const std::size_t c = block_of(neighbor[k]);
            if (c != b) ++row[c];
        }
    });
    slot_first.assign(count + 1, 0);
    by_target_first.resize(count * count + 1);
    by_target_first[0] = 0;
    for (std::size_t b = 0; b < count; ++b) {
        std::int32_t in_block = 0;
        for (std::size_t c = 0; c < count; ++c) {
            in_block += per_pair[b * count + c];
            by_target_first[b * count + c + 1] = by_target_first[b * count + c] + per_pair[b * count + c];
        }
        slot_first[b + 1] = slot_first[b] + in_block;
    }
    halo_disk.resize(static_cast<std::size_t>(slot_first[count]));
    by_target.resize(halo_disk.size());
    parallel_for_blocks(count, [&](std::size_t b) {
        std::vector<std::int32_t> next(by_target_first.begin() + static_cast<std::ptrdiff_t>(b * count),
                                       by_target_first.begin() + static_cast<std::ptrdiff_t>((b + 1) * count));
        std::int32_t slot = slot_first[b];  // in list order, as the force loop counts them
        for (auto k = static_cast<std::size_t>(entry_first[b]); k < static_cast<std::size_t>(entry_first[b + 1]); ++k) {
            const std::int32_t j = neighbor[k];
            const std::size_t c = block_of(j);
            if (c == b) continue;
            halo_disk[static_cast<std::size_t>(slot)] = j;
            by_target[static_cast<std::size_t>(next[c]++)] = slot;
            ++slot;
        }
    });
}

}  // namespace jamsim

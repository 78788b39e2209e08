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
    target.resize(neighbor.size());
    // Halo entries per (source block, target block), then their slots laid out in that order.
    std::vector<std::int32_t> per_pair(count * count, 0);
    parallel_for_blocks(count, [&](std::size_t b) {
        std::int32_t* row = per_pair.data() + b * count;
        for (auto k = static_cast<std::size_t>(entry_first[b]); k < static_cast<std::size_t>(entry_first[b + 1]); ++k) {
            const std::size_t c = block_of(neighbor[k]);
            if (c != b) ++row[c];
        }
    });
    halo_first.resize(count * count + 1);
    halo_first[0] = 0;
    for (std::size_t q = 0; q < count * count; ++q) halo_first[q + 1] = halo_first[q] + per_pair[q];
    halo_disk.resize(static_cast<std::size_t>(halo_first.back()));
    parallel_for_blocks(count, [&](std::size_t b) {
        std::vector<std::int32_t> next(halo_first.begin() + static_cast<std::ptrdiff_t>(b * count),
                                       halo_first.begin() + static_cast<std::ptrdiff_t>((b + 1) * count));
        for (auto k = static_cast<std::size_t>(entry_first[b]); k < static_cast<std::size_t>(entry_first[b + 1]); ++k) {
            const std::int32_t j = neighbor[k];
            const std::size_t c = block_of(j);
            if (c == b) {
                target[k] = j;
            } else {
                const std::int32_t slot = next[c]++;
                target[k] = ~slot;
                halo_disk[static_cast<std::size_t>(slot)] = j;
            }
        }
    });
}

} // namespace jamsim

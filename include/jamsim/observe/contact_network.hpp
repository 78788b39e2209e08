#pragma once
#include <cstdint>
#include <vector>

#include "jamsim/core/system.hpp"
#include "jamsim/force/pair_forces.hpp"
#include "jamsim/neighbor/neighbor_list.hpp"

namespace jamsim {

/// The contact network of a (minimised) configuration with its rattlers removed: a disk with
/// fewer than 3 contacts (d + 1 in two dimensions, frictionless) cannot be held in force
/// balance by repulsive contacts, so it and its contacts are removed, repeatedly, until every
/// remaining disk has at least 3 (Paper II).
struct ContactNetwork {
    std::vector<std::uint8_t> rattler;  ///< per disk: 1 if removed
    std::vector<Contact> contacts;      ///< contacts among non-rattlers (list order)
    std::int64_t all_contacts = 0;      ///< N_c before removal
    std::int64_t nonrattlers = 0;       ///< N′

    std::int64_t backbone_contacts() const { return static_cast<std::int64_t>(contacts.size()); }
    /// Z = 2 N_c′ / N′ (0 without non-rattlers).
    double z() const;
    double rattler_fraction() const;
    /// Contacts above the isostatic count N_c,iso = 2(N′ − 1) + 1 of a jammed periodic
    /// packing at fixed box (2 per non-rattler, less 2 for global translation, plus 1 for a
    /// positive pressure): 0 at isostaticity.
    std::int64_t excess_contacts() const;
};

/// Build it from the list's pairs in contact at the current positions.
ContactNetwork contact_network(const System& sys, const NeighborList& list);

}  // namespace jamsim

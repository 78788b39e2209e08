#include "jamsim/observe/contact_network.hpp"

namespace jamsim {

double ContactNetwork::z() const {
    return nonrattlers ? 2.0 * static_cast<double>(contacts.size()) / static_cast<double>(nonrattlers) : 0.0;
}

double ContactNetwork::rattler_fraction() const {
    return rattler.empty() ? 0.0 : 1.0 - static_cast<double>(nonrattlers) / static_cast<double>(rattler.size());
}

std::int64_t ContactNetwork::excess_contacts() const { return backbone_contacts() - (2 * (nonrattlers - 1) + 1); }

ContactNetwork contact_network(const System& sys, const NeighborList& list) {
    const Particles& p = sys.particles;
    ContactNetwork net;
    std::vector<Contact> all = find_contacts(list, sys.box, p.x, p.y);
    net.all_contacts = static_cast<std::int64_t>(all.size());
    std::vector<int> degree(p.size(), 0);
    for (const auto& c : all) {
        ++degree[c.i];
        ++degree[c.j];
    }
    net.rattler.assign(p.size(), 0);
    std::vector<std::uint8_t> alive(all.size(), 1);
    // Remove disks with < 3 live contacts until none is left (each pass is O(N_c); the number
    // of passes is the longest chain of cascading removals, small in practice).
    for (bool changed = true; changed;) {
        changed = false;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (!net.rattler[i] && degree[i] < 3) {
                net.rattler[i] = 1;
                changed = true;
            }
        if (!changed) break;
        for (std::size_t k = 0; k < all.size(); ++k) {
            if (!alive[k]) continue;
            if (net.rattler[all[k].i] || net.rattler[all[k].j]) {
                alive[k] = 0;
                --degree[all[k].i];
                --degree[all[k].j];
            }
        }
    }
    for (std::size_t k = 0; k < all.size(); ++k)
        if (alive[k]) net.contacts.push_back(all[k]);
    for (auto r : net.rattler) net.nonrattlers += r ? 0 : 1;
    return net;
}

}  // namespace jamsim

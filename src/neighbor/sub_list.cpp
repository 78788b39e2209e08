#include "jamsim/neighbor/sub_list.hpp"

#include <algorithm>
#include <cmath>

namespace jamsim {

bool SubList::update(const NeighborList& parent, const Box& box, std::span<const double> x, std::span<const double> y) {
    // The parent's rule with this skin; max_contact_ bounds |s_y| of a pair that touches, as
    // d_max does there.
    if (parent.builds() == parent_builds_ &&
        !verlet_rule_broken(x, y, x_ref_, y_ref_, box.strain(), strain_ref_, max_contact_ + skin_, skin_))
        return false;
    const auto owner = parent.owner(), neighbor = parent.neighbor();
    const auto sx = parent.shift_x(), sy = parent.shift_y(), contact = parent.contact();
    owner_.clear();
    neighbor_.clear();
    parent_entry_.clear();
    shift_x_.clear();
    shift_y_.clear();
    contact_.clear();
    max_contact_ = 0.0;
    for (std::size_t k = 0; k < parent.size(); ++k) {
        const auto i = static_cast<std::size_t>(owner[k]);
        const auto j = static_cast<std::size_t>(neighbor[k]);
        max_contact_ = std::max(max_contact_, contact[k]);
        const Vec2 r = box.lab(x[i] - x[j] + sx[k], y[i] - y[j] + sy[k]);
        const double reach = contact[k] + skin_;
        if (r.x * r.x + r.y * r.y >= reach * reach) continue;
        owner_.push_back(owner[k]);
        neighbor_.push_back(neighbor[k]);
        parent_entry_.push_back(static_cast<std::uint32_t>(k));
        shift_x_.push_back(sx[k]);
        shift_y_.push_back(sy[k]);
        contact_.push_back(contact[k]);
    }
    x_ref_.assign(x.begin(), x.end());
    y_ref_.assign(y.begin(), y.end());
    strain_ref_ = box.strain();
    parent_builds_ = parent.builds();
    ++builds_;
    return true;
}

}  // namespace jamsim

#include "jamsim/force/force_field.hpp"

#include "jamsim/parallel/threads.hpp"

namespace jamsim {

ForceResult ForceField::compute(System& sys, Tally tally) {
    Particles& p = sys.particles;
    if (list_.needs_rebuild(p.x, p.y, sys.box)) {
        parallel_for(p.size(), [&](std::size_t i) { sys.box.wrap_into_cell(p.x[i], p.y[i]); });
        p.permute(spatial_order(p, sys.box, max_diameter(p) + list_.skin()));
        list_.build(p.x, p.y, p.diameter, sys.box);
    }
    const ContactRecord record = start_record(sys.box, p.x, p.y);
    return compute_pair_forces(pot_, list_, sys.box, p.x, p.y, p.fx, p.fy, scratch_, tally, record);
}

ForceResult ForceField::compute_at(const Box& box, std::span<const double> x, std::span<const double> y,
                                   std::span<const double> diameter, std::span<double> fx, std::span<double> fy,
                                   Tally tally) {
    if (list_.needs_rebuild(x, y, box)) list_.build(x, y, diameter, box);
    const ContactRecord record = start_record(box, x, y);
    return compute_pair_forces(pot_, list_, box, x, y, fx, fy, scratch_, tally, record);
}

ContactRecord ForceField::start_record(const Box& box, std::span<const double> x, std::span<const double> y) {
    recorded_ = recording_;
    if (!recording_) return {};
    touching_.resize(list_.size());
    sum_ry_.resize(x.size());
    recorded_x_ = x.data();
    recorded_y_ = y.data();
    recorded_strain_ = box.strain();
    recorded_builds_ = list_.builds();
    return {.touching = touching_.data(), .sum_ry = sum_ry_.data()};
}

std::optional<ForceField::RecordedContacts> ForceField::recorded_contacts(const Box& box, std::span<const double> x,
                                                                          std::span<const double> y) const {
    if (!recorded_ || x.data() != recorded_x_ || y.data() != recorded_y_ || x.size() != sum_ry_.size() ||
        box.strain() != recorded_strain_ || recorded_builds_ != list_.builds() || touching_.size() != list_.size())
        return std::nullopt;
    return RecordedContacts{touching_, sum_ry_};
}

ForceResult ForceField::compute_split(const Box& box, std::span<const double> x_total, std::span<const double> y_total,
                                      std::span<const double> base_x, std::span<const double> base_y,
                                      std::span<const double> off_x, std::span<const double> off_y,
                                      std::span<const double> diameter, std::span<double> fx, std::span<double> fy,
                                      Tally tally, double displacement_bound) {
    const bool check = displacement_bound < 0.0 || list_.may_need_rebuild(displacement_bound, box);
    if (check && list_.needs_rebuild(x_total, y_total, box)) list_.build(x_total, y_total, diameter, box);
    recorded_ = false;  // a minimiser's evaluation: nothing recorded
    return compute_pair_forces_split(pot_, list_, box, base_x, base_y, off_x, off_y, fx, fy, scratch_, tally);
}

void drift(std::span<double> x, std::span<double> y, std::span<const double> vx, std::span<const double> vy,
           double gamma, double scale) {
    parallel_for(x.size(), [&](std::size_t i) {
        x[i] += scale * (vx[i] - gamma * vy[i]);
        y[i] += scale * vy[i];
    });
}

void apply_strain(System& sys, ForceField& forces, double strain) {
    sys.box.set_strain_unwrapped(strain);
    const int wraps = sys.box.finish_shear();
    if (wraps != 0) {
        sys.box.remap_after_wrap(wraps, sys.particles.x, sys.particles.y);
        forces.invalidate();
    }
}

}  // namespace jamsim

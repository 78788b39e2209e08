#include <stdexcept>

#include "jamsim/minimize/minimizer.hpp"

namespace jamsim {

std::unique_ptr<Minimizer> make_conjugate_gradient();
std::unique_ptr<Minimizer> make_polak_ribiere();
std::unique_ptr<Minimizer> make_fire();

std::string_view to_string(MinimizeOutcome outcome) {
    switch (outcome) {
    case MinimizeOutcome::Unjammed: return "unjammed";
    case MinimizeOutcome::ForceBalanced: return "force_balanced";
    case MinimizeOutcome::NotConverged: return "not_converged";
    }
    return "?";
}

std::vector<std::string> minimizer_names() { return {"cg", "cg-pr", "fire"}; }

std::unique_ptr<Minimizer> make_minimizer(std::string_view name) {
    if (name == "cg") return make_conjugate_gradient();
    if (name == "cg-pr") return make_polak_ribiere();
    if (name == "fire") return make_fire();
    throw std::invalid_argument("unknown minimiser '" + std::string(name) + "': allowed cg, cg-pr, fire");
}

}  // namespace jamsim

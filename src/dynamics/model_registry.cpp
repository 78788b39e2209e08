#include <stdexcept>
#include <string>

#include "jamsim/dynamics/model.hpp"
#include "jamsim/dynamics/cd0.hpp"
#include "jamsim/dynamics/rd0.hpp"
#include "jamsim/dynamics/sllod.hpp"

namespace jamsim {

namespace {
struct Entry {
    const char* name;
    std::unique_ptr<Model> (*make)(const ModelParams&);
};
// One line per model: adding a model is its own file plus a line here.
constexpr Entry kModels[] = {
    {"RD0", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Rd0>(p); }},
    {"CD0", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Cd0>(p); }},
    {"RD", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Sllod>(p, Damping::RD, "RD"); }},
    {"CD", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Sllod>(p, Damping::CD, "CD"); }},
    {"CDn", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Sllod>(p, Damping::CDn, "CDn"); }},
    {"CDt", [](const ModelParams& p) -> std::unique_ptr<Model> { return std::make_unique<Sllod>(p, Damping::CDt, "CDt"); }},
};
} // namespace

std::vector<std::string> model_names() {
    std::vector<std::string> names;
    for (const auto& e : kModels) names.emplace_back(e.name);
    return names;
}

std::unique_ptr<Model> make_model(std::string_view name, const ModelParams& params) {
    for (const auto& e : kModels)
        if (name == e.name) return e.make(params);
    std::string known;
    for (const auto& n : model_names()) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("unknown model '" + std::string(name) + "' (known: " + known + ")");
}

} // namespace jamsim

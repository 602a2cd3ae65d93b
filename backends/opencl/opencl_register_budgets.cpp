#include "backends/opencl/opencl_register_budgets.h"

#include <array>
#include <charconv>
#include <map>
#include <sstream>
#include <string_view>

#include "core/render/backend.h"
#include "core/util/environment.h"
#include "core/util/error.h"

namespace prism::opencl {
namespace {

// Prism's budgets, for work-groups of 128, CUDA's: intersect, occlude and shadow at 64 registers (8 groups per SM, as
// __launch_bounds__ holds CUDA's), shade at 128 (4 groups, where nvcc puts CUDA's by itself). Left to itself,
// NVIDIA's OpenCL compiler gives the shade kernel more, fewer groups fit, and the stage runs slower
// (docs/kernels.md, "Register budgets on OpenCL"). The one-mesh walks (intersect_mesh, occlude_mesh) at 56, 9 groups,
// as CUDA's. Stages not named take what the compiler chooses.
unsigned default_budget(Stage stage) {
    switch (stage) {
        case Stage::Intersect:
        case Stage::Occlude:
        case Stage::Shadow: return 64u;
        case Stage::IntersectMesh:
        case Stage::OccludeMesh: return 56u;
        case Stage::Shade: return 128u;
        default: return 0u;
    }
}

constexpr uint32_t all_stages = (1u << stage_count) - 1u;
static_assert(stage_count < 32, "RT_CL_STAGE_MASK is a 32-bit mask");

[[noreturn]] void bad_setting(const std::string& value, const std::string& why) {
    throw Error(std::string("opencl: ") + setting_name(Setting::OpenclRegisters) + "='" + shorten(value) + "': " + why);
}

// Stage -> budget from "shade=128,intersect=64" ("none" or "": no budgets).
std::array<unsigned, stage_count> parse_budgets(const std::string& value) {
    std::array<unsigned, stage_count> budgets{};
    if (value.empty() || value == "none") return budgets;
    if (value.back() == ',') bad_setting(value, "an empty item after the last comma");
    std::istringstream items(value);
    std::string item;
    while (std::getline(items, item, ',')) {
        const size_t eq = item.find('=');
        if (eq == std::string::npos) bad_setting(value, "'" + item + "' is not stage=registers");
        const std::string name = item.substr(0, eq);
        size_t stage = 0;
        while (stage < stage_count && name != stage_name(Stage(stage))) ++stage;
        if (stage == stage_count) bad_setting(value, "no stage is named '" + name + "'");
        std::string_view number = std::string_view(item).substr(eq + 1);
        unsigned registers = 0;
        auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), registers);
        // NVIDIA GPUs address 255 registers a thread; fewer than 16 is no budget a kernel can meet.
        if (ec != std::errc() || end != number.data() + number.size() || registers < 16 || registers > 255) {
            std::string why = "'";  // appended, not prepended: GCC 12 warns (-Wrestrict) on "'" + string
            why.append(number).append("' is not a register count from 16 to 255");
            bad_setting(value, why);
        }
        budgets[stage] = registers;
    }
    return budgets;
}

}  // namespace

std::vector<StageProgram> stage_programs(bool nv_register_option, const std::optional<std::string>& budgets_setting) {
    std::array<unsigned, stage_count> budgets{};
    if (budgets_setting) {
        budgets = parse_budgets(*budgets_setting);
    } else {
        for (size_t s = 0; s < stage_count; ++s) budgets[s] = default_budget(Stage(s));
    }
    if (!nv_register_option) budgets.fill(0);
    std::map<unsigned, uint32_t> stages_by_budget;
    for (size_t s = 0; s < stage_count; ++s) stages_by_budget[budgets[s]] |= 1u << s;
    std::vector<StageProgram> programs;
    for (const auto& [budget, stages] : stages_by_budget) {
        StageProgram program{"", stages};
        // All stages in one program: no mask, so the program (and its cache entry) is the plain one.
        if (stages != all_stages) program.options = "-D RT_CL_STAGE_MASK=" + std::to_string(stages) + "u";
        if (budget) program.options += " -cl-nv-maxrregcount=" + std::to_string(budget);
        if (!program.options.empty() && program.options[0] == ' ') program.options.erase(0, 1);
        programs.push_back(program);
    }
    return programs;
}

}  // namespace prism::opencl

// Register budgets per stage, the OpenCL twin of CUDA's __launch_bounds__ (backends/cuda/stages.cu). OpenCL C has no
// per-kernel spelling for it; NVIDIA's compiler takes -cl-nv-maxrregcount (cl_nv_compiler_options) for a whole
// program, so the stages are built as one program per budget, each holding only its stages' entry points
// (RT_CL_STAGE_MASK, stages.cl). Devices without that extension get one program and the compiler's choice.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace prism::opencl {

// One program to build: its extra build options and its stages (bit i: line i of kernels/stage_list.h).
struct StageProgram {
    std::string options;
    uint32_t stages = 0;
};

// The programs that cover every stage once. `budgets_setting` is $PRISM_OPENCL_REGISTERS when set: a comma list of
// stage=registers (a stage not named has none) or "none", in place of Prism's table; it is ignored, as the table
// is, where `nv_register_option` is false. Throws prism::Error "opencl: PRISM_OPENCL_REGISTERS='<value>': <why>".
std::vector<StageProgram> stage_programs(bool nv_register_option, const std::optional<std::string>& budgets_setting);

}  // namespace prism::opencl

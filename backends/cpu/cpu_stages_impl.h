// The body of one stage runner (backends/cpu/cpu_stages.h), included once per instruction set with
// PRISM_CPU_STAGE_RUNNER naming the function. No include guard.
#include "backends/cpu/cpu_stages.h"
#include "kernels/stages.h"

namespace prism::cpu {

void PRISM_CPU_STAGE_RUNNER(Stage stage, KernelGlobals kg, uint32_t depth) {
    switch (stage) {
#define RT_STAGE(name, Name, pass, launch, needs) \
    case Stage::Name:                             \
        rt_kernel_##name(kg, depth);              \
        break;
#include "kernels/stage_list.h"
#undef RT_STAGE
        case Stage::Count: break;
    }
}

}  // namespace prism::cpu

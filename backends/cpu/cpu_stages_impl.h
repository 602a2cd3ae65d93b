// The body of one stage runner (backends/cpu/cpu_stages.h), included once per instruction set with
// PRISM_CPU_STAGE_RUNNER naming the function. No include guard.
#include "backends/cpu/cpu_stages.h"
#include "kernels/stages.h"

namespace prism::cpu {

void PRISM_CPU_STAGE_RUNNER(Stage stage, KernelGlobals kg, uint32_t depth) {
    switch (stage) {
        case Stage::Generate: rt_kernel_generate(kg, depth); break;
        case Stage::Intersect: rt_kernel_intersect(kg, depth); break;
        case Stage::Miss: rt_kernel_miss(kg, depth); break;
        case Stage::Shade: rt_kernel_shade(kg, depth); break;
        case Stage::Shadow: rt_kernel_shadow(kg, depth); break;
        case Stage::Resolve: rt_kernel_resolve(kg, depth); break;
        case Stage::Count: break;
    }
}

}  // namespace prism::cpu

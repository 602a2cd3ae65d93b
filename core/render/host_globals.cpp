#include "core/render/host_globals.h"

namespace prism {

KernelGlobals host_globals(const DeviceScene& scene, FrameParams* frame, uint32_t* accum, uint32_t* image,
                           float4* radiance) {
    KernelGlobals kg{};
#define RT_DATA_ARRAY(slot, type, name, access, role) \
    PRISM_IF_SCENE_ARRAY(role, kg.name = const_cast<::type*>(scene.name.data());)
#include "kernels/data_arrays.h"
#undef RT_DATA_ARRAY
    kg.frame = frame;
    kg.accum = accum;
    kg.image = image;
    kg.radiance = radiance;
    return kg;
}

}  // namespace prism

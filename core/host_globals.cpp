#include "core/host_globals.h"

namespace prism {

KernelGlobals host_globals(const DeviceScene& scene, FrameParams* frame, uint32_t* accum, uint32_t* image,
                           float4* radiance) {
    KernelGlobals kg{};
    kg.nodes = const_cast<BvhNode*>(scene.nodes.data());
    kg.wide_nodes = const_cast<BvhWideNode*>(scene.wide_nodes.data());
    kg.instances = const_cast<::Instance*>(scene.instances.data());
    kg.triangles = const_cast<TriangleGeometry*>(scene.triangles.data());
    kg.triangle_blocks = const_cast<TriangleBlock*>(scene.triangle_blocks.data());
    kg.triangle_shading = const_cast<TriangleShading*>(scene.triangle_shading.data());
    kg.vertices = const_cast<Vertex*>(scene.vertices.data());
    kg.materials = const_cast<::Material*>(scene.materials.data());
    kg.texture_layers = const_cast<::TextureLayer*>(scene.texture_layers.data());
    kg.texture_infos = const_cast<TextureInfo*>(scene.texture_infos.data());
    kg.texels = const_cast<uint32_t*>(scene.texels.data());
    kg.lights = const_cast<::Light*>(scene.lights.data());
    kg.frame = frame;
    kg.accum = accum;
    kg.image = image;
    kg.radiance = radiance;
    return kg;
}

}  // namespace prism

// THE list of device arrays. One line per buffer generates: the KernelGlobals pointer struct (C++/CUDA/OpenCL),
// the OpenCL kernel parameter list, the GLSL buffer blocks and the Vulkan binding numbers (the first column),
// and the host-side upload table (core/device_scene.h). Adding a buffer is one line here.
//
// RT_DATA_ARRAY(binding, element type, name, access)   access: ro (stages only read) or rw
// No include guard: it is expanded several times with different definitions of RT_DATA_ARRAY.
RT_DATA_ARRAY(0, BvhNode, nodes, ro)          // the top-level BVH first (root 0), then every mesh's BVH
RT_DATA_ARRAY(1, Instance, instances, ro)
RT_DATA_ARRAY(2, TriangleGeometry, triangles, ro)
RT_DATA_ARRAY(3, TriangleShading, triangle_shading, ro)
RT_DATA_ARRAY(4, Vertex, vertices, ro)
RT_DATA_ARRAY(5, Material, materials, ro)
RT_DATA_ARRAY(6, TextureLayer, texture_layers, ro)
RT_DATA_ARRAY(7, TextureInfo, texture_infos, ro)
RT_DATA_ARRAY(8, uint, texels, ro)
RT_DATA_ARRAY(9, Light, lights, ro)
RT_DATA_ARRAY(10, FrameParams, frame, ro)
RT_DATA_ARRAY(11, Ray, rays, rw)
RT_DATA_ARRAY(12, Hit, hits, rw)
RT_DATA_ARRAY(13, ShadowRay, shadow_rays, rw)
RT_DATA_ARRAY(14, uint, counters, rw)
RT_DATA_ARRAY(15, uint, accum, rw)
RT_DATA_ARRAY(16, uint, image, rw)
RT_DATA_ARRAY(17, float4, radiance, rw)
RT_DATA_ARRAY(18, BvhWideNode, wide_nodes, ro)         // the wide layout's nodes (top level first); else one unused
RT_DATA_ARRAY(19, TriangleBlock, triangle_blocks, ro)  // the wide layout's leaf triangles; else one unused block

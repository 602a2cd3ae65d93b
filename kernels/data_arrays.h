// THE list of device arrays. One line per array generates: the KernelGlobals pointer struct (C++/CUDA/OpenCL), the
// OpenCL kernel parameters, the GLSL buffer blocks and their Vulkan bindings (the first column), the DeviceArray enum
// and names (core/render/backend.h), and, for the scene arrays, DeviceScene's storage (core/render/device_scene.h),
// their upload (core/render/renderer.cpp) and the reference renderer's pointers (core/render/host_globals.cpp). Adding
// an array: its element struct in types.h (with its layout_table.h row) and one line here.
//
// RT_DATA_ARRAY(binding, element type, name, access, role)
//   access  ro: the stages only read it; rw: they write it
//   role    scene: built once per scene (DeviceScene) and uploaded with it; frame: the frame's parameters and queue
//           counts, written by the host every frame; queue: rays, hits and shadow rays, sized by the renderer from
//           the queue capacity; pixel: one entry (or a few words) per pixel of the frame or tile
// No include guard: it is expanded several times with different definitions of RT_DATA_ARRAY.
RT_DATA_ARRAY(0, BvhNode, nodes, ro, scene)  // the top-level BVH first (root 0), then every mesh's BVH
RT_DATA_ARRAY(1, Instance, instances, ro, scene)
RT_DATA_ARRAY(2, TriangleGeometry, triangles, ro, scene)
RT_DATA_ARRAY(3, TriangleShading, triangle_shading, ro, scene)
RT_DATA_ARRAY(4, Vertex, vertices, ro, scene)
RT_DATA_ARRAY(5, Material, materials, ro, scene)
RT_DATA_ARRAY(6, TextureLayer, texture_layers, ro, scene)
RT_DATA_ARRAY(7, TextureInfo, texture_infos, ro, scene)
RT_DATA_ARRAY(8, uint, texels, ro, scene)
RT_DATA_ARRAY(9, Light, lights, ro, scene)  // a placeholder when the scene has no light
RT_DATA_ARRAY(10, FrameParams, frame, ro, frame)
RT_DATA_ARRAY(11, Ray, rays, rw, queue)
RT_DATA_ARRAY(12, Hit, hits, rw, queue)
RT_DATA_ARRAY(13, ShadowRay, shadow_rays, rw, queue)
RT_DATA_ARRAY(14, uint, counters, rw, frame)
RT_DATA_ARRAY(15, uint, accum, rw, pixel)
RT_DATA_ARRAY(16, uint, image, rw, pixel)
RT_DATA_ARRAY(17, float4, radiance, rw, pixel)
// The wide layout's nodes (top level first) and leaf triangles; one unused entry each in the other layouts.
RT_DATA_ARRAY(18, BvhWideNode, wide_nodes, ro, scene)
RT_DATA_ARRAY(19, TriangleBlock, triangle_blocks, ro, scene)

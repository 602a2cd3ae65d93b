// THE list of wavefront stages, in the order a frame launches them. Everything that names a stage comes from it:
// the Stage enum, its names and the frame loop (core/render/backend.h, core/render/renderer.cpp), the CUDA and OpenCL
// entry points and launches, the cpu backend's dispatch, and Vulkan's shader set and indirect launches
// (backends/*/CMakeLists.txt read these lines). Adding a stage: its rt_kernel_<name> in kernels/stages.h and one line
// here.
//
// RT_STAGE(name, Name, pass, launch, needs)
//   name    the stage's function is rt_kernel_<name>(kg, depth) (kernels/stages.h)
//   Name    its prism::Stage enumerator
//   pass    Before: once before the bounces (depth 0); Bounce: once per depth; After: once after the bounces
//   launch  how many items it runs over, which decides how Vulkan launches it:
//           Grid            the fixed grid, sized by the host
//           GridSizesQueue  the fixed grid; the ray queue's counts are final when it runs, so on Vulkan it also
//                           writes the indirect-dispatch arguments of the Queue stages after it
//           Queue           the rays queued at its depth (Vulkan launches it indirectly)
//           QueueGrows      as Queue, and it appends rays: the dispatch arguments are stale after it
//   needs   0: every frame launches it; an RT_FLAG_* bit: only frames with that flag do (the others would launch it
//           for nothing). A GridSizesQueue stage always runs: the indirect launches after it need its arguments.
//
// No include guard: it is expanded several times with different definitions of RT_STAGE.
RT_STAGE(generate, Generate, Before, GridSizesQueue, 0)
RT_STAGE(intersect, Intersect, Bounce, Queue, 0)
// Ray queries for any hit (Renderer::trace): a stage of its own, so that each kernel holds one walk.
RT_STAGE(occlude, Occlude, Bounce, Queue, RT_FLAG_ANY_HIT)
// The same two for one instance in the stack layout (RT_FLAG_MESH_WALK): kernels of the one-mesh walk.
RT_STAGE(intersect_mesh, IntersectMesh, Bounce, Queue, RT_FLAG_MESH_WALK)
RT_STAGE(occlude_mesh, OccludeMesh, Bounce, Queue, RT_FLAG_ANY_HIT_MESH_WALK)
RT_STAGE(miss, Miss, Bounce, Queue, 0)
RT_STAGE(shade, Shade, Bounce, QueueGrows, 0)
RT_STAGE(shadow, Shadow, Bounce, GridSizesQueue, 0)
RT_STAGE(shadow_layers, ShadowLayers, Bounce, Grid, RT_FLAG_ALPHA_SHADOWS)
RT_STAGE(resolve, Resolve, After, Grid, 0)

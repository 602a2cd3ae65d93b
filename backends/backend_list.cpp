// Registers every backend this build has: before main() in every program that links this file (Prism::prism makes
// sure it is linked), and again, harmlessly, when a program calls register_builtin_backends() itself.
#include "backends/backend_list.h"

#include "backends/cpu/cpu_backend.h"
#ifdef PRISM_HAVE_CUDA
#include "backends/cuda/cuda_backend.h"
#endif
#ifdef PRISM_HAVE_OPENCL
#include "backends/opencl/opencl_backend.h"
#endif
#ifdef PRISM_HAVE_VULKAN
#include "backends/vulkan/vulkan_backend.h"
#endif

namespace prism {

void register_builtin_backends() {
    register_backend(cpu_backend_factory());
#ifdef PRISM_HAVE_CUDA
    register_backend(cuda_backend_factory());
#endif
#ifdef PRISM_HAVE_OPENCL
    register_backend(opencl_backend_factory());
#endif
#ifdef PRISM_HAVE_VULKAN
    register_backend(vulkan_backend_factory());
#endif
}

}  // namespace prism

// A C name, so that the linker option of Prism::prism (backends/CMakeLists.txt) can name it.
extern "C" const bool prism_builtin_backends_registered = (prism::register_builtin_backends(), true);

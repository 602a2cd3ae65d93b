// Whether a backend named as the user writes it ("vulkan", "opencl:pocl") can run here, asked of its registered
// probe before anything is built for it (a BVH in another layout, buffers, a context).
#pragma once

#include <string>

namespace prism::viewer {

// Empty when it can run; otherwise why not ("not compiled in", the probe's reason, "no device matches 'x'").
std::string why_backend_unavailable(const std::string& spec);

}  // namespace prism::viewer

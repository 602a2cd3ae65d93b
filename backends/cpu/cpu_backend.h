// The `cpu` backend: the kernels/ stages over device-style arrays in host memory, launched on a thread pool.
// It makes no decision a GPU backend could not make on the device: it runs the same stage schedule.
#pragma once

#include <memory>

#include "core/render/backend.h"

namespace prism {

BackendFactory cpu_backend_factory();

}  // namespace prism

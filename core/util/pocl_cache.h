// PoCL will not start without its kernel-cache folder: when it cannot create $POCL_CACHE_DIR (else
// $XDG_CACHE_HOME/pocl/kcache, else $HOME/.cache/pocl/kcache), its platform reports no devices and the opencl
// backend is gone ("platforms without devices: Portable Computing Language"). A cache must never cost a backend,
// so before the first OpenCL call (the opencl backend, `prism bandwidth`) Prism checks that folder and, when it
// cannot be created or written, points POCL_CACHE_DIR at a fresh private folder for this run, with one warning on
// stderr. In core (no OpenCL header needed) because both of those callers need it, like device_memory_limit.h.
#pragma once

#include <string>

namespace prism {

// Idempotent; the first call does the work. Returns the warning it printed ("" when PoCL's folder was usable).
std::string ensure_pocl_cache_dir();

}  // namespace prism

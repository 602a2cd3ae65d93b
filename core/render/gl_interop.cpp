#include "core/render/gl_interop.h"

#include "core/util/error.h"

namespace prism {

// Each API implements the one of the two that fits who owns its memory; the viewer asks device_owns_memory() first.
void GlInterop::attach_gl_buffer(uint32_t, size_t) {
    throw Error(name() + ": the device allocates the shared buffer (use export_buffer)");
}

ExportedBuffer GlInterop::export_buffer(size_t) {
    throw Error(name() + ": GL allocates the shared buffer (use attach_gl_buffer)");
}

}  // namespace prism

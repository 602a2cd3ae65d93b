// The GL half of the Vulkan-GL path and of CUDA-GL through external memory: device memory exported by the backend
// (an opaque fd; Vulkan's a dedicated allocation, CUDA's not) imported as a GL memory object and given to a buffer
// object with glNamedBufferStorageMemEXT, plus the two shared semaphores when the backend exported them (Vulkan;
// GL_EXT_memory_object_fd, GL_EXT_semaphore_fd).
#pragma once

#include <cstddef>

#include "core/render/gl_interop.h"
#include "core/util/non_copyable.h"
#include "viewer/gl_external.h"

namespace prism::viewer {

class ImportedBuffer : private NonCopyable {
public:
    // Takes ownership of the fds in `exported` (closing them itself when the import fails). Throws prism::Error
    // naming the GL call that failed. Needs a current context with GL_EXT_memory_object_fd.
    ImportedBuffer(const ExportedBuffer& exported, size_t bytes);
    ~ImportedBuffer();

    GLuint buffer() const { return buffer_; }
    bool has_semaphores() const { return ready_ != 0; }
    // Semaphore path: before reading the buffer, wait for the device's copy; after, tell the device GL is done.
    void wait_ready();
    void signal_released();

private:
    void release();

    GlExternalFunctions gl_;
    GLuint memory_ = 0, buffer_ = 0, ready_ = 0, released_ = 0;
};

}  // namespace prism::viewer

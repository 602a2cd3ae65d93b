#include "viewer/gl_memory_import.h"

#include <unistd.h>

#include <cstdio>
#include <string>

#include "core/util/error.h"

namespace prism::viewer {
namespace {

void check_gl(const char* what) {
    GLenum error = glGetError();
    if (error == GL_NO_ERROR) return;
    while (glGetError() != GL_NO_ERROR) {
    }
    throw Error(std::string("view: ") + what + " failed (GL error 0x" + [&] {
        char text[16];
        std::snprintf(text, sizeof text, "%04x", error);
        return std::string(text);
    }() + ")");
}

void close_fd(int& fd) {
    if (fd >= 0) ::close(fd);
    fd = -1;
}

}  // namespace

ImportedBuffer::ImportedBuffer(const ExportedBuffer& exported, size_t bytes) : gl_(load_gl_external_functions()) {
    int memory_fd = exported.memory_fd, ready_fd = exported.ready_semaphore_fd,
        released_fd = exported.released_semaphore_fd;
    try {
        if (!gl_.memory_object_fd) throw Error("view: GL lost GL_EXT_memory_object_fd");
        while (glGetError() != GL_NO_ERROR) {
        }
        gl_.create_memory_objects(1, &memory_);
        // Must match the export: Vulkan allocated it dedicated to the one buffer.
        GLint dedicated = exported.dedicated ? GL_TRUE : GL_FALSE;
        gl_.memory_object_parameteriv(memory_, kGlDedicatedMemoryObject, &dedicated);
        gl_.import_memory_fd(memory_, exported.allocation_size, kGlHandleTypeOpaqueFd, memory_fd);
        check_gl("glImportMemoryFdEXT");
        memory_fd = -1;  // GL owns it now
        glGenBuffers(1, &buffer_);
        glBindBuffer(GL_TEXTURE_BUFFER, buffer_);  // binding once creates the object the named call needs
        glBindBuffer(GL_TEXTURE_BUFFER, 0);
        gl_.named_buffer_storage_mem(buffer_, GLsizeiptr(bytes), memory_, 0);
        check_gl("glNamedBufferStorageMemEXT");
        if (ready_fd >= 0 && released_fd >= 0) {
            if (!gl_.semaphore_fd)
                throw Error("view: the backend exported semaphores but GL has no GL_EXT_semaphore_fd");
            gl_.gen_semaphores(1, &ready_);
            gl_.import_semaphore_fd(ready_, kGlHandleTypeOpaqueFd, ready_fd);
            check_gl("glImportSemaphoreFdEXT");
            ready_fd = -1;
            gl_.gen_semaphores(1, &released_);
            gl_.import_semaphore_fd(released_, kGlHandleTypeOpaqueFd, released_fd);
            check_gl("glImportSemaphoreFdEXT");
            released_fd = -1;
        }
    } catch (...) {
        close_fd(memory_fd);
        close_fd(ready_fd);
        close_fd(released_fd);
        release();
        throw;
    }
}

ImportedBuffer::~ImportedBuffer() { release(); }

void ImportedBuffer::release() {
    if (buffer_) glDeleteBuffers(1, &buffer_);
    if (memory_ && gl_.delete_memory_objects) gl_.delete_memory_objects(1, &memory_);
    if (ready_ && gl_.delete_semaphores) gl_.delete_semaphores(1, &ready_);
    if (released_ && gl_.delete_semaphores) gl_.delete_semaphores(1, &released_);
    buffer_ = memory_ = ready_ = released_ = 0;
}

void ImportedBuffer::wait_ready() {
    // A buffer barrier only: the draw reads the buffer through a buffer texture, no image layout to convert.
    gl_.wait_semaphore(ready_, 1, &buffer_, 0, nullptr, nullptr);
}

void ImportedBuffer::signal_released() {
    gl_.signal_semaphore(released_, 1, &buffer_, 0, nullptr, nullptr);
    // The device's next copy waits on this semaphore while the host waits on the device's fence: the signal must
    // reach the GPU now, not at GL's next flush, or both would wait forever.
    glFlush();
}

}  // namespace prism::viewer

#include "viewer/gl_external.h"

#include <cstring>
#include <type_traits>

namespace prism::viewer {
namespace {

GlProcAddress proc_address = nullptr;

}  // namespace

void set_gl_proc_address(GlProcAddress lookup) { proc_address = lookup; }

bool gl_has_extension(const char* name) {
    GLint count = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &count);
    for (GLint i = 0; i < count; ++i) {
        const GLubyte* extension = glGetStringi(GL_EXTENSIONS, GLuint(i));
        if (extension && std::strcmp(reinterpret_cast<const char*>(extension), name) == 0) return true;
    }
    return false;
}

GlExternalFunctions load_gl_external_functions() {
    GlExternalFunctions f;
    auto load = [](auto& pointer, const char* name) {
        GlFunction function = proc_address ? proc_address(name) : nullptr;
        pointer = reinterpret_cast<std::remove_reference_t<decltype(pointer)>>(function);
        return pointer != nullptr;
    };
    bool memory = gl_has_extension("GL_EXT_memory_object") && gl_has_extension("GL_EXT_memory_object_fd");
    memory &= load(f.create_memory_objects, "glCreateMemoryObjectsEXT");
    memory &= load(f.delete_memory_objects, "glDeleteMemoryObjectsEXT");
    memory &= load(f.memory_object_parameteriv, "glMemoryObjectParameterivEXT");
    memory &= load(f.named_buffer_storage_mem, "glNamedBufferStorageMemEXT");
    memory &= load(f.get_unsigned_bytev, "glGetUnsignedBytevEXT");
    memory &= load(f.get_unsigned_bytei_v, "glGetUnsignedBytei_vEXT");
    memory &= load(f.import_memory_fd, "glImportMemoryFdEXT");
    f.memory_object_fd = memory;
    bool semaphore = gl_has_extension("GL_EXT_semaphore") && gl_has_extension("GL_EXT_semaphore_fd");
    semaphore &= load(f.gen_semaphores, "glGenSemaphoresEXT");
    semaphore &= load(f.delete_semaphores, "glDeleteSemaphoresEXT");
    semaphore &= load(f.wait_semaphore, "glWaitSemaphoreEXT");
    semaphore &= load(f.signal_semaphore, "glSignalSemaphoreEXT");
    semaphore &= load(f.import_semaphore_fd, "glImportSemaphoreFdEXT");
    f.semaphore_fd = semaphore;
    return f;
}

}  // namespace prism::viewer

// GL_EXT_memory_object(_fd) and GL_EXT_semaphore(_fd), the GL half of the Vulkan-GL path. They are not in
// glcorearb.h and not every libGL exports them, so they are looked up once a context is current, through the
// window system that made it (glfwGetProcAddress, eglGetProcAddress).
#pragma once

#include "viewer/gl.h"

namespace prism::viewer {

inline constexpr GLenum kGlDedicatedMemoryObject = 0x9581;  // GL_DEDICATED_MEMORY_OBJECT_EXT
inline constexpr GLenum kGlHandleTypeOpaqueFd = 0x9586;     // GL_HANDLE_TYPE_OPAQUE_FD_EXT
inline constexpr GLenum kGlNumDeviceUuids = 0x9596;         // GL_NUM_DEVICE_UUIDS_EXT
inline constexpr GLenum kGlDeviceUuid = 0x9597;             // GL_DEVICE_UUID_EXT
inline constexpr GLenum kGlDriverUuid = 0x9598;             // GL_DRIVER_UUID_EXT

struct GlExternalFunctions {
    // GL_EXT_memory_object
    void(APIENTRYP create_memory_objects)(GLsizei n, GLuint* objects) = nullptr;
    void(APIENTRYP delete_memory_objects)(GLsizei n, const GLuint* objects) = nullptr;
    void(APIENTRYP memory_object_parameteriv)(GLuint object, GLenum name, const GLint* value) = nullptr;
    void(APIENTRYP named_buffer_storage_mem)(GLuint buffer, GLsizeiptr size, GLuint memory, GLuint64 offset) = nullptr;
    void(APIENTRYP get_unsigned_bytev)(GLenum name, GLubyte* data) = nullptr;
    void(APIENTRYP get_unsigned_bytei_v)(GLenum target, GLuint index, GLubyte* data) = nullptr;
    // GL_EXT_memory_object_fd
    void(APIENTRYP import_memory_fd)(GLuint memory, GLuint64 size, GLenum handle_type, GLint fd) = nullptr;
    // GL_EXT_semaphore
    void(APIENTRYP gen_semaphores)(GLsizei n, GLuint* semaphores) = nullptr;
    void(APIENTRYP delete_semaphores)(GLsizei n, const GLuint* semaphores) = nullptr;
    void(APIENTRYP wait_semaphore)(GLuint semaphore, GLuint buffer_count, const GLuint* buffers, GLuint texture_count,
                                   const GLuint* textures, const GLenum* layouts) = nullptr;
    void(APIENTRYP signal_semaphore)(GLuint semaphore, GLuint buffer_count, const GLuint* buffers, GLuint texture_count,
                                     const GLuint* textures, const GLenum* layouts) = nullptr;
    // GL_EXT_semaphore_fd
    void(APIENTRYP import_semaphore_fd)(GLuint semaphore, GLenum handle_type, GLint fd) = nullptr;

    bool memory_object_fd = false;  // the context lists both extensions and every function above resolved
    bool semaphore_fd = false;
};

// How GL functions are looked up for the current context: set by the window that made it current.
using GlFunction = void (*)();
using GlProcAddress = GlFunction (*)(const char* name);
void set_gl_proc_address(GlProcAddress lookup);

// The current context's functions (looked up on every call: a backend switch keeps the context, so this is cheap
// to keep simple).
GlExternalFunctions load_gl_external_functions();

// Whether the current context lists `name` (glGetStringi).
bool gl_has_extension(const char* name);

}  // namespace prism::viewer

#include "viewer/native_handles.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GLFW_EXPOSE_NATIVE_X11
#define GLFW_EXPOSE_NATIVE_GLX
#include <GLFW/glfw3native.h>

namespace prism::viewer {

NativeGlHandles native_gl_handles(GLFWwindow* window) {
    NativeGlHandles handles;
    // Both return null (and report a GLFW error, which the window's callback records) when the platform or
    // context API differs: the OpenCL-GL path then says it needs a GLX context.
    handles.x11_display = reinterpret_cast<uintptr_t>(glfwGetX11Display());
    handles.glx_context = reinterpret_cast<uintptr_t>(glfwGetGLXContext(window));
    return handles;
}

}  // namespace prism::viewer

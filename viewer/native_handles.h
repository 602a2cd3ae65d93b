// The window system's handles of a GLFW window's GL context: in a file of its own because <GLFW/glfw3native.h>
// brings <GL/glx.h> and with it <GL/gl.h>, which cannot share a translation unit with <GL/glcorearb.h>.
#pragma once

#include <cstdint>

struct GLFWwindow;

namespace prism::viewer {

struct NativeGlHandles {
    uintptr_t x11_display = 0;  // Display*; 0 when the window is not on X11
    uintptr_t glx_context = 0;  // GLXContext; 0 when the context is not a GLX one (EGL)
};
NativeGlHandles native_gl_handles(GLFWwindow* window);

}  // namespace prism::viewer

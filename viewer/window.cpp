#include "viewer/window.h"

#include <chrono>
#include <cstring>

#include "core/util/error.h"
#include "viewer/gl.h"
#include "viewer/gl_external.h"
#include "viewer/glfw_window.h"
#include "viewer/offscreen_window.h"

namespace prism::viewer {
namespace {

const char* gl_string(GLenum name) {
    const GLubyte* text = glGetString(name);
    return text ? reinterpret_cast<const char*>(text) : "?";
}

}  // namespace

void Window::describe_context(const std::string& via) {
    context_description_ = std::string("OpenGL ") + gl_string(GL_VERSION) + " on " + gl_string(GL_RENDERER);
    if (!via.empty()) context_description_ += " via " + via;
}

std::vector<uint32_t> Window::read_pixels() const {
    int width = framebuffer_width(), height = framebuffer_height();
    std::vector<uint32_t> bottom_up(size_t(width) * size_t(height));
    glFinish();
    uint32_t framebuffer = draw_framebuffer();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    glReadBuffer(framebuffer == 0 ? GL_BACK : GL_COLOR_ATTACHMENT0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottom_up.data());
    if (GLenum error = glGetError(); error != GL_NO_ERROR)
        throw Error("view: glReadPixels failed (GL error " + std::to_string(error) + ")");
    // GL's row 0 is the bottom one; images here start at the top. RGBA bytes are r-low words on little endian.
    std::vector<uint32_t> top_down(bottom_up.size());
    for (int y = 0; y < height; ++y)
        std::memcpy(&top_down[size_t(y) * width], &bottom_up[size_t(height - 1 - y) * width], size_t(width) * 4);
    for (uint32_t& pixel : top_down) pixel |= 0xff000000u;
    return top_down;
}

GlContextHandles Window::gl_context_handles() const {
    GlContextHandles gl;
    native_handles(gl);
    gl.renderer = gl_string(GL_RENDERER);
    GlExternalFunctions external = load_gl_external_functions();
    gl.memory_object_fd = external.memory_object_fd;
    gl.semaphore_fd = external.semaphore_fd;
    if (external.memory_object_fd) {
        GLint devices = 0;
        glGetIntegerv(kGlNumDeviceUuids, &devices);
        if (devices > 0) external.get_unsigned_bytei_v(kGlDeviceUuid, 0, gl.device_uuid.data());
        external.get_unsigned_bytev(kGlDriverUuid, gl.driver_uuid.data());
    }
    while (glGetError() != GL_NO_ERROR) {
    }
    return gl;
}

void Window::receive_drop(const std::vector<std::string>& paths) {
    pending_.dropped.insert(pending_.dropped.end(), paths.begin(), paths.end());
}

double input_clock() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::unique_ptr<Window> open_window(const std::string& title, int width, int height, bool vsync, bool headless) {
    if (headless) return std::make_unique<OffscreenWindow>(width, height);
    return std::make_unique<GlfwWindow>(title, width, height, vsync);
}

}  // namespace prism::viewer

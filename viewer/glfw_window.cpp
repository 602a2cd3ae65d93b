#include "viewer/glfw_window.h"

#include <cstdlib>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/error.h"
#include "viewer/gl_external.h"
#include "viewer/native_handles.h"

namespace prism::viewer {
namespace {

std::string last_glfw_error;

void record_glfw_error(int, const char* description) { last_glfw_error = description ? description : "unknown"; }

Error cannot_open(const std::string& why) { return Error("view: cannot open a window (" + why + ")"); }

bool has_display() {
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    return (x11 && *x11) || (wayland && *wayland);
}

GLFWwindow* create_window(const std::string& title, int width, int height, int major, int minor) {
    glfwDefaultWindowHints();
    glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, major);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, minor);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    // The frame is shown 1:1; a resized window would need a re-render at the new size (not done yet).
    glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);   // the frame is already sRGB-encoded: pass bytes through
    return glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
}

GlfwWindow* owner(GLFWwindow* window) { return static_cast<GlfwWindow*>(glfwGetWindowUserPointer(window)); }

}  // namespace

GlfwWindow::GlfwWindow(const std::string& title, int width, int height, bool vsync) {
    if (!has_display()) throw cannot_open("no DISPLAY; run under xvfb-run -a");
    glfwSetErrorCallback(record_glfw_error);
    if (!glfwInit()) throw cannot_open("GLFW: " + last_glfw_error);
    window_ = create_window(title, width, height, 4, 5);
    if (!window_) window_ = create_window(title, width, height, 3, 3);
    if (!window_) {
        std::string why = last_glfw_error;
        glfwTerminate();
        throw cannot_open("no OpenGL 4.5 or 3.3 core context: " + why);
    }
    glfwMakeContextCurrent(window_);
    set_gl_proc_address(glfwGetProcAddress);
    glfwSwapInterval(vsync ? 1 : 0);
    describe_context();
    glfwSetWindowUserPointer(window_, this);
    glfwSetKeyCallback(window_, on_key);
    glfwSetCursorPosCallback(window_, on_cursor);
    glfwSetMouseButtonCallback(window_, on_mouse_button);
    glfwSetScrollCallback(window_, on_scroll);
}

GlfwWindow::~GlfwWindow() {
    set_gl_proc_address(nullptr);
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_); }

Input GlfwWindow::poll() {
    glfwPollEvents();
    Input input = std::move(pending_);
    pending_ = Input{};
    auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS ? 1.0f : 0.0f; };
    input.fly = {held(GLFW_KEY_D) - held(GLFW_KEY_A), held(GLFW_KEY_E) - held(GLFW_KEY_Q),
                 held(GLFW_KEY_W) - held(GLFW_KEY_S)};
    return input;
}

void GlfwWindow::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
void GlfwWindow::swap() { glfwSwapBuffers(window_); }

int GlfwWindow::framebuffer_width() const {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    return width;
}

int GlfwWindow::framebuffer_height() const {
    int width = 0, height = 0;
    glfwGetFramebufferSize(window_, &width, &height);
    return height;
}

void GlfwWindow::native_handles(GlContextHandles& gl) const {
    NativeGlHandles native = native_gl_handles(window_);
    gl.x11_display = native.x11_display;
    gl.glx_context = native.glx_context;
}

void GlfwWindow::on_key(GLFWwindow* window, int key, int, int action, int mods) {
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    GlfwWindow* self = owner(window);
    auto push = [&](Action a) { self->pending_.actions.push_back(a); };
    bool repeat = action == GLFW_REPEAT;
    switch (key) {
    case GLFW_KEY_1: if (!repeat) push(Action::Backend1); break;
    case GLFW_KEY_2: if (!repeat) push(Action::Backend2); break;
    case GLFW_KEY_3: if (!repeat) push(Action::Backend3); break;
    case GLFW_KEY_4: if (!repeat) push(Action::Backend4); break;
    case GLFW_KEY_5: if (!repeat) push(Action::Backend5); break;
    case GLFW_KEY_KP_ADD: push(Action::DepthUp); break;
    case GLFW_KEY_EQUAL: push(Action::DepthUp); break;   // '+' is shift+'=' on US layouts; take both
    case GLFW_KEY_KP_SUBTRACT: push(Action::DepthDown); break;
    case GLFW_KEY_MINUS: push(Action::DepthDown); break;
    case GLFW_KEY_P: if (!repeat) push(Action::Screenshot); break;
    case GLFW_KEY_R: if (!repeat) push(Action::ResetCamera); break;
    case GLFW_KEY_M: if (!repeat) push(Action::ToggleMoving); break;
    case GLFW_KEY_ESCAPE: push(Action::Quit); break;
    default: break;
    }
    (void)mods;
}

void GlfwWindow::on_cursor(GLFWwindow* window, double x, double y) {
    GlfwWindow* self = owner(window);
    glm::dvec2 cursor{x, y};
    if (self->dragging_) self->pending_.drag += glm::vec2(cursor - self->last_cursor_);
    self->last_cursor_ = cursor;
}

void GlfwWindow::on_mouse_button(GLFWwindow* window, int button, int action, int) {
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    GlfwWindow* self = owner(window);
    self->dragging_ = action == GLFW_PRESS;
    glfwGetCursorPos(window, &self->last_cursor_.x, &self->last_cursor_.y);
}

void GlfwWindow::on_scroll(GLFWwindow* window, double, double y) { owner(window)->pending_.scroll += float(y); }

}  // namespace prism::viewer

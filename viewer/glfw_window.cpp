#include "viewer/glfw_window.h"

#include <cstdlib>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>

#include "core/util/error.h"
#include "viewer/gl_external.h"
#include "viewer/native_handles.h"
#include "viewer/panel.h"

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
    // Resizable: the session renders at the framebuffer's new size (Input::resized).
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);  // the frame is already sRGB-encoded: pass bytes through
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
    glfwSetDropCallback(window_, on_drop);
    glfwSetFramebufferSizeCallback(window_, on_framebuffer_size);
    glfwSetCharCallback(window_, on_char);
    glfwSetWindowFocusCallback(window_, on_focus);
    glfwSetCursorEnterCallback(window_, on_cursor_enter);
}

GlfwWindow::~GlfwWindow() {
    set_gl_proc_address(nullptr);
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

bool GlfwWindow::should_close() const { return glfwWindowShouldClose(window_); }

Input GlfwWindow::poll() {
    glfwPollEvents();
    return take_pending();
}

Input GlfwWindow::wait(double timeout_seconds) {
    if (timeout_seconds > 0.0)
        glfwWaitEventsTimeout(timeout_seconds);
    else
        glfwPollEvents();
    return take_pending();
}

Input GlfwWindow::take_pending() {
    Input input = std::move(pending_);
    pending_ = Input{};
    return input;
}

void* GlfwWindow::glfw_window() const { return window_; }

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

// Fly keys are held keys: their presses and releases go to viewer/held_keys.h with the time they were seen.
static bool fly_key(int key, FlyKey* fly) {
    switch (key) {
        case GLFW_KEY_W: *fly = FlyKey::Forward; return true;
        case GLFW_KEY_S: *fly = FlyKey::Back; return true;
        case GLFW_KEY_A: *fly = FlyKey::Left; return true;
        case GLFW_KEY_D: *fly = FlyKey::Right; return true;
        case GLFW_KEY_Q: *fly = FlyKey::Down; return true;
        case GLFW_KEY_E: *fly = FlyKey::Up; return true;
        default: return false;
    }
}

void GlfwWindow::on_key(GLFWwindow* window, int key, int scancode, int action, int mods) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
    GlfwWindow* self = owner(window);
    self->pending_.other = true;
    FlyKey fly;
    if (fly_key(key, &fly)) {
        if (action != GLFW_REPEAT) self->pending_.fly_keys.push_back({fly, action == GLFW_PRESS, input_clock()});
        return;
    }
    if (action != GLFW_PRESS && action != GLFW_REPEAT) return;
    auto push = [&](Action a) { self->pending_.actions.push_back(a); };
    bool repeat = action == GLFW_REPEAT;
    switch (key) {
        case GLFW_KEY_1:
            if (!repeat) push(Action::Backend1);
            break;
        case GLFW_KEY_2:
            if (!repeat) push(Action::Backend2);
            break;
        case GLFW_KEY_3:
            if (!repeat) push(Action::Backend3);
            break;
        case GLFW_KEY_4:
            if (!repeat) push(Action::Backend4);
            break;
        case GLFW_KEY_5:
            if (!repeat) push(Action::Backend5);
            break;
        case GLFW_KEY_KP_ADD: push(Action::DepthUp); break;
        case GLFW_KEY_EQUAL: push(Action::DepthUp); break;  // '+' is shift+'=' on US layouts; take both
        case GLFW_KEY_KP_SUBTRACT: push(Action::DepthDown); break;
        case GLFW_KEY_MINUS: push(Action::DepthDown); break;
        case GLFW_KEY_LEFT_BRACKET: push(Action::ExposureDown); break;
        case GLFW_KEY_RIGHT_BRACKET: push(Action::ExposureUp); break;
        case GLFW_KEY_T:
            if (!repeat) push(Action::ToggleToneMap);
            break;
        case GLFW_KEY_P:
            if (!repeat) push(Action::Screenshot);
            break;
        case GLFW_KEY_R:
            if (!repeat) push(Action::ResetCamera);
            break;
        case GLFW_KEY_M:
            if (!repeat) push(Action::ToggleMoving);
            break;
        case GLFW_KEY_F:
            if (!repeat) push(Action::FrameScene);
            break;
        case GLFW_KEY_H:
            if (!repeat) push(Action::ToggleHelp);
            break;
        case GLFW_KEY_F1:
            if (!repeat) push(Action::ToggleHelp);
            break;
        case GLFW_KEY_L:
            if (!repeat) push(Action::Reload);
            break;
        case GLFW_KEY_ESCAPE: push(Action::Quit); break;
        default: break;
    }
}

// The cursor's position in framebuffer pixels (window coordinates scaled, for displays that scale windows).
void GlfwWindow::on_cursor(GLFWwindow* window, double x, double y) {
    GlfwWindow* self = owner(window);
    self->pending_.other = true;
    glm::dvec2 cursor{x, y};
    glm::vec2 moved(cursor - self->last_cursor_);
    if (self->drag_ == Drag::Orbit) self->pending_.drag += moved;
    if (self->drag_ == Drag::Pan) self->pending_.pan += moved;
    self->last_cursor_ = cursor;
}

void GlfwWindow::on_mouse_button(GLFWwindow* window, int button, int action, int mods) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_MouseButtonCallback(window, button, action, mods);
    GlfwWindow* self = owner(window);
    self->pending_.other = true;
    glfwGetCursorPos(window, &self->last_cursor_.x, &self->last_cursor_.y);
    if (action == GLFW_RELEASE) {
        self->drag_ = Drag::None;
        return;
    }
    if (Panel::wants_mouse()) return;  // a click on the panel is the panel's
    if (button == GLFW_MOUSE_BUTTON_MIDDLE) self->drag_ = Drag::Pan;
    if (button == GLFW_MOUSE_BUTTON_LEFT) self->drag_ = (mods & GLFW_MOD_SHIFT) ? Drag::Pan : Drag::Orbit;
}

void GlfwWindow::on_scroll(GLFWwindow* window, double x, double y) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_ScrollCallback(window, x, y);
    GlfwWindow* self = owner(window);
    self->pending_.other = true;
    if (!Panel::wants_mouse()) self->pending_.scroll += float(y);
}

void GlfwWindow::on_drop(GLFWwindow* window, int count, const char** paths) {
    owner(window)->receive_drop(std::vector<std::string>(paths, paths + count));
}

void GlfwWindow::on_framebuffer_size(GLFWwindow* window, int, int) { owner(window)->pending_.resized = true; }

void GlfwWindow::on_char(GLFWwindow* window, unsigned int codepoint) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_CharCallback(window, codepoint);
}

void GlfwWindow::on_focus(GLFWwindow* window, int focused) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_WindowFocusCallback(window, focused);
    owner(window)->pending_.other = true;
}

void GlfwWindow::on_cursor_enter(GLFWwindow* window, int entered) {
    if (ImGui::GetCurrentContext()) ImGui_ImplGlfw_CursorEnterCallback(window, entered);
    owner(window)->pending_.other = true;
}

}  // namespace prism::viewer

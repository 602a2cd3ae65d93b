#include "viewer/panel.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "core/util/error.h"
#include "viewer/controls_help.h"

namespace prism::viewer {
namespace {

ImVec4 error_colour() { return ImVec4(1.0f, 0.45f, 0.4f, 1.0f); }

void help_overlay() {
    ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                            ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("Controls (H or F1 closes)", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings);
    if (ImGui::BeginTable("controls", 2, ImGuiTableFlags_RowBg)) {
        for (const ControlHelp& control : controls_help()) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(control.input);
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(control.action);
        }
        ImGui::EndTable();
    }
    ImGui::End();
}

}  // namespace

Panel::Panel(Window& window) : window_(window) {
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // no imgui.ini left in the working directory
    ImGui::StyleColorsDark();
    if (void* glfw = window.glfw_window()) {
        // The window's own callbacks forward to the backend's (viewer/glfw_window.cpp): no callbacks installed.
        ImGui_ImplGlfw_InitForOpenGL(static_cast<GLFWwindow*>(glfw), false);
        glfw_ = true;
    }
    if (!ImGui_ImplOpenGL3_Init("#version 330 core")) {
        if (glfw_) ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        throw Error(
            "view: the panel cannot start (Dear ImGui's OpenGL 3 backend could not load GL's functions "
            "through libGL.so.1)");
    }
    last_time_ = input_clock();
}

Panel::~Panel() {
    ImGui_ImplOpenGL3_Shutdown();
    if (glfw_) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

bool Panel::wants_mouse() { return ImGui::GetCurrentContext() && ImGui::GetIO().WantCaptureMouse; }

PanelRequest Panel::draw(const PanelView& view, bool help) {
    // Dear ImGui measures a window that fits its contents in its first frame and shows it from the next: the
    // first panel is laid out once unseen, so that even a one-frame session shows it.
    if (!laid_out_) {
        build(view, help);
        ImGui::EndFrame();
        laid_out_ = true;
    }
    PanelRequest request = build(view, help);
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    return request;
}

PanelRequest Panel::build(const PanelView& view, bool help) {
    PanelRequest request;
    ImGui_ImplOpenGL3_NewFrame();
    if (glfw_) {
        ImGui_ImplGlfw_NewFrame();
    } else {
        ImGuiIO& io = ImGui::GetIO();
        io.DisplaySize = ImVec2(float(window_.framebuffer_width()), float(window_.framebuffer_height()));
        double now = input_clock();
        io.DeltaTime = now > last_time_ ? float(now - last_time_) : 1.0f / 60.0f;
        last_time_ = now;
    }
    ImGui::NewFrame();

    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.75f);
    ImGui::Begin("Prism", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings);
    // Wrapped lines at a fixed width: a window that fits its contents has no width of its own to wrap at.
    ImGui::PushTextWrapPos(ImGui::GetFontSize() * 22.0f);
    ImGui::TextWrapped("%s", view.scene.c_str());
    ImGui::Text("%s [%s]", view.backend.c_str(), view.device.c_str());
    if (view.frame_ms > 0.0)
        ImGui::Text("%.1f fps (%.1f ms per frame)", view.fps, view.frame_ms);
    else
        ImGui::TextUnformatted("fps: - (no frames in a row yet)");
    ImGui::Text("render %.1f ms, %.1f Mrays/s", view.render_ms, view.mrays_per_second);
    if (ImGui::TreeNode("stages", "per stage (ms)")) {
        for (const auto& [name, ms] : view.stage_ms) ImGui::Text("%-10s %8.2f", name.c_str(), ms);
        ImGui::TreePop();
    }
    ImGui::Text("frame %ux%u, window %ux%u", view.render_width, view.render_height, view.window_width,
                view.window_height);
    ImGui::TextUnformatted(view.activity.c_str());
    ImGui::Text("frames rendered %llu, shown %llu", static_cast<unsigned long long>(view.frames_rendered),
                static_cast<unsigned long long>(view.frames_shown));
    ImGui::TextWrapped("%s", view.display_path.c_str());

    int depth = int(view.depth);
    if (ImGui::SliderInt("depth", &depth, 1, 32) && depth != int(view.depth)) request.depth = uint32_t(depth);
    float exposure = view.exposure;
    if (ImGui::SliderFloat("exposure (EV)", &exposure, -10.0f, 10.0f, "%+.1f") && exposure != view.exposure)
        request.exposure = exposure;
    bool tone_map = view.tone_map;
    if (ImGui::Checkbox("tone map (T)", &tone_map) && tone_map != view.tone_map) request.tone_map = tone_map;
    int current = -1;
    for (size_t i = 0; i < view.backends.size(); ++i)
        if (view.backends[i] == view.backend) current = int(i);
    if (ImGui::BeginCombo("backend", view.backend.c_str())) {
        for (size_t i = 0; i < view.backends.size(); ++i)
            if (ImGui::Selectable(view.backends[i].c_str(), int(i) == current) && int(i) != current)
                request.backend = view.backends[i];
        ImGui::EndCombo();
    }
    if (ImGui::Button("reload (L)")) request.reload = true;
    ImGui::SameLine();
    if (ImGui::Button(help ? "hide help (H)" : "help (H)")) request.toggle_help = true;
    if (!view.message.empty()) {
        if (view.message_is_error) ImGui::PushStyleColor(ImGuiCol_Text, error_colour());
        ImGui::TextWrapped("%s", view.message.c_str());
        if (view.message_is_error) ImGui::PopStyleColor();
    }
    ImGui::PopTextWrapPos();
    ImGui::End();
    if (help) help_overlay();
    return request;
}

}  // namespace prism::viewer

#include "viewer/controls_help.h"

namespace prism::viewer {

std::span<const ControlHelp> controls_help() {
    static const ControlHelp table[] = {
        {"left drag", "orbit around the target"},
        {"middle drag, Shift + left drag", "pan"},
        {"scroll wheel", "zoom toward / away from the target"},
        {"W / S, A / D, Q / E (held)", "fly forward / back, left / right, down / up"},
        {"F", "frame the whole scene"},
        {"R", "reset the camera to the scene's"},
        {"1 2 3 4 5", "backend: cpu-ref, cpu, cuda, opencl, vulkan"},
        {"+ / -", "ray depth up / down"},
        {"[ / ]", "exposure half a stop down / up"},
        {"T", "tone map (Khronos PBR Neutral) on / off"},
        {"M", "play / pause the scene's animation (else the moving object)"},
        {"P", "screenshot (prism-view-NNNN.png, never overwritten)"},
        {"L", "reload the current scene file"},
        {"drop a file", "load a scene (.gltf .glb .obj .ply .json) or an environment (.hdr, cube-map folder)"},
        {"H, F1", "show / hide this help"},
        {"Esc", "quit"},
    };
    return table;
}

}  // namespace prism::viewer

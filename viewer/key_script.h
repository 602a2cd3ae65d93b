// What the keys do, independent of GLFW, and `--keys`: a scripted key sequence for tests and demos
// ("FRAME:KEY,..." — each key is pressed once, just before that frame is rendered).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace prism::viewer {

enum class Action {
    Backend1, Backend2, Backend3, Backend4, Backend5,   // cpu-ref, cpu, cuda, opencl, vulkan
    DepthUp, DepthDown,
    Screenshot,
    ResetCamera,
    ToggleMoving,
    Quit,
    // One fly step (a held key in the window moves continuously instead).
    FlyForward, FlyBack, FlyLeft, FlyRight, FlyDown, FlyUp,
};

// The backend each of the keys 1-5 selects.
const char* backend_for_key(Action action);   // nullptr for other actions
bool is_backend_key(Action action);

// Key names as written in --keys and the docs: 1-5, +, -, P, R, M, Esc, W, A, S, D, Q, E (case-insensitive).
// Throws prism::Error naming the unknown key.
Action parse_key(const std::string& name);

struct ScriptedKey {
    uint32_t frame;
    Action action;
};
// "0:M,3:2,4:P" -> sorted by frame, order kept within a frame. Throws prism::Error ("--keys: ...") on bad input.
std::vector<ScriptedKey> parse_key_script(const std::string& text);

}  // namespace prism::viewer

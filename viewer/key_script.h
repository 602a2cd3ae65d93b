// What the keys do, independent of GLFW, and `--keys`: a scripted key sequence for tests and demos
// ("FRAME:KEY,..." — each key is pressed once, just before that frame is rendered; a fly key is held, for
// FRAME:KEY:SECONDS or a default tap, through the same viewer/held_keys.h path as a key held in the window).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "viewer/held_keys.h"

namespace prism::viewer {

enum class Action {
    Backend1,
    Backend2,
    Backend3,
    Backend4,
    Backend5,  // cpu-ref, cpu, cuda, opencl, vulkan
    DepthUp,
    DepthDown,
    Screenshot,
    ResetCamera,
    ToggleMoving,
    Quit,
    FrameScene,     // F: the whole scene in view
    ToggleHelp,     // H or F1: the help overlay listing every control
    Reload,         // L: load the current scene file again
    ExposureDown,   // [: half a stop darker
    ExposureUp,     // ]: half a stop brighter
    ToggleToneMap,  // T: the Khronos PBR Neutral tone map on / off
    // Fly keys in a script (the window reports them as held keys instead: Input::fly_keys).
    FlyForward,
    FlyBack,
    FlyLeft,
    FlyRight,
    FlyDown,
    FlyUp,
};

// The held key a scripted fly action stands for; false for other actions.
bool fly_key_for(Action action, FlyKey* key);

// The backend each of the keys 1-5 selects.
const char* backend_for_key(Action action);  // nullptr for other actions
bool is_backend_key(Action action);

// Key names as written in --keys and the docs: 1-5, +, -, [, ], T, P, R, M, F, H, L, Esc, W, A, S, D, Q, E
// (case-insensitive).
// Throws prism::Error naming the unknown key.
Action parse_key(const std::string& name);

// How long a scripted fly key without SECONDS is held.
inline constexpr double kScriptedTapSeconds = 0.25;

struct ScriptedKey {
    uint32_t frame;
    Action action;
    double hold_seconds = 0.0;  // fly keys: how long the key is held, ending just before the frame
};
// "0:M,3:2,4:P,5:W:1.5" -> sorted by frame, order kept within a frame. SECONDS (> 0, at most 3600) only after a
// fly key. Throws prism::Error ("--keys: ...") on bad input.
std::vector<ScriptedKey> parse_key_script(const std::string& text);

}  // namespace prism::viewer

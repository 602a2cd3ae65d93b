#include "viewer/key_script.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "core/util/error.h"

namespace prism::viewer {

const char* backend_for_key(Action action) {
    switch (action) {
        case Action::Backend1: return "cpu-ref";
        case Action::Backend2: return "cpu";
        case Action::Backend3: return "cuda";
        case Action::Backend4: return "opencl";
        case Action::Backend5: return "vulkan";
        default: return nullptr;
    }
}

bool is_backend_key(Action action) { return backend_for_key(action) != nullptr; }

bool fly_key_for(Action action, FlyKey* key) {
    switch (action) {
        case Action::FlyForward: *key = FlyKey::Forward; return true;
        case Action::FlyBack: *key = FlyKey::Back; return true;
        case Action::FlyLeft: *key = FlyKey::Left; return true;
        case Action::FlyRight: *key = FlyKey::Right; return true;
        case Action::FlyDown: *key = FlyKey::Down; return true;
        case Action::FlyUp: *key = FlyKey::Up; return true;
        default: return false;
    }
}

Action parse_key(const std::string& name) {
    std::string key;
    for (char c : name) key += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    static const std::pair<const char*, Action> table[] = {
        {"1", Action::Backend1},     {"2", Action::Backend2},    {"3", Action::Backend3},
        {"4", Action::Backend4},     {"5", Action::Backend5},    {"+", Action::DepthUp},
        {"-", Action::DepthDown},    {"P", Action::Screenshot},  {"R", Action::ResetCamera},
        {"M", Action::ToggleMoving}, {"ESC", Action::Quit},      {"F", Action::FrameScene},
        {"H", Action::ToggleHelp},   {"F1", Action::ToggleHelp}, {"L", Action::Reload},
        {"W", Action::FlyForward},   {"S", Action::FlyBack},     {"A", Action::FlyLeft},
        {"D", Action::FlyRight},     {"Q", Action::FlyDown},     {"E", Action::FlyUp},
        {"[", Action::ExposureDown}, {"]", Action::ExposureUp},  {"T", Action::ToggleToneMap},
    };
    for (const auto& [text, action] : table)
        if (key == text) return action;
    throw Error("--keys: unknown key '" + name + "' (use 1-5, +, -, [, ], T, P, R, M, F, H, L, Esc, W, A, S, D, Q, E)");
}

std::vector<ScriptedKey> parse_key_script(const std::string& text) {
    std::vector<ScriptedKey> script;
    size_t start = 0;
    while (start <= text.size() && !text.empty()) {
        size_t end = text.find(',', start);
        if (end == std::string::npos) end = text.size();
        std::string item = text.substr(start, end - start);
        size_t colon = item.find(':');
        if (colon == std::string::npos || colon == 0 || colon + 1 >= item.size())
            throw Error("--keys: expected FRAME:KEY, got '" + item + "'");
        std::string frame = item.substr(0, colon);
        if (!std::all_of(frame.begin(), frame.end(),
                         [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }) ||
            frame.size() > 9)
            throw Error("--keys: bad frame number '" + frame + "' in '" + item + "'");
        std::string key = item.substr(colon + 1);
        double hold = 0.0;
        size_t second_colon = key.find(':');
        if (second_colon != std::string::npos) {
            std::string seconds = key.substr(second_colon + 1);
            key = key.substr(0, second_colon);
            char* end = nullptr;
            hold = std::strtod(seconds.c_str(), &end);
            if (seconds.empty() || *end != '\0' || !(hold > 0.0 && hold <= 3600.0))
                throw Error("--keys: bad hold time '" + seconds + "' in '" + item + "' (seconds, > 0, at most 3600)");
        }
        Action action = parse_key(key);
        FlyKey fly;
        bool is_fly = fly_key_for(action, &fly);
        if (hold > 0.0 && !is_fly)
            throw Error("--keys: only the fly keys W A S D Q E take a hold time, not '" + item + "'");
        if (is_fly && hold == 0.0) hold = kScriptedTapSeconds;
        script.push_back({static_cast<uint32_t>(std::stoul(frame)), action, hold});
        start = end + 1;
    }
    std::stable_sort(script.begin(), script.end(),
                     [](const ScriptedKey& a, const ScriptedKey& b) { return a.frame < b.frame; });
    return script;
}

}  // namespace prism::viewer

#include "viewer/held_keys.h"

namespace prism::viewer {

void HeldKeys::press(FlyKey key, double time) {
    State& state = keys_[size_t(key)];
    if (state.down) return;
    state.down = true;
    state.since = time;
}

void HeldKeys::release(FlyKey key, double time) {
    State& state = keys_[size_t(key)];
    if (!state.down) return;
    state.down = false;
    if (time > state.since) state.held += time - state.since;
}

glm::vec3 HeldKeys::collect(double now) {
    std::array<float, 6> seconds{};
    for (size_t i = 0; i < keys_.size(); ++i) {
        State& state = keys_[i];
        double total = state.held;
        if (state.down && now > state.since) {
            total += now - state.since;
            state.since = now;
        }
        state.held = 0.0;
        seconds[i] = float(total);
    }
    auto at = [&](FlyKey key) { return seconds[size_t(key)]; };
    return {at(FlyKey::Right) - at(FlyKey::Left), at(FlyKey::Up) - at(FlyKey::Down),
            at(FlyKey::Forward) - at(FlyKey::Back)};
}

bool HeldKeys::any_down() const {
    for (const State& state : keys_)
        if (state.down) return true;
    return false;
}

void HeldKeys::release_all(double time) {
    for (size_t i = 0; i < keys_.size(); ++i) release(FlyKey(i), time);
}

}  // namespace prism::viewer

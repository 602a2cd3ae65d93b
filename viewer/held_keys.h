// The fly keys (W/S, A/D, Q/E) held in real time. The window reports each press and release with the time it saw
// it; every input update asks how long each key was down since the previous update. So a held key moves the
// camera by the time it was really held, whatever the frame rate, and a tap between two updates still counts.
// `--keys` holds (FRAME:W:SECONDS) go through the same presses and releases.
#pragma once

#include <array>

#include <glm/glm.hpp>

namespace prism::viewer {

enum class FlyKey { Forward, Back, Left, Right, Down, Up };

class HeldKeys {
public:
    // A press of a key already down (key repeat) and a release of a key that is up are ignored.
    void press(FlyKey key, double time);
    void release(FlyKey key, double time);
    // Seconds each key was down between the previous collect and `now`, as a signed vector in camera axes
    // (x right - left, y up - down, z forward - back).
    glm::vec3 collect(double now);
    bool any_down() const;
    void release_all(double time);

private:
    struct State {
        bool down = false;
        double since = 0.0;  // when it went down, or the last collect while down
        double held = 0.0;   // seconds down not collected yet, from presses already released
    };
    std::array<State, 6> keys_{};
};

}  // namespace prism::viewer

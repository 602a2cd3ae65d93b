// `prism view`'s input and preview logic as units: fly keys timed by how long they are held (the held-key bug of
// issue 18 was a step computed from the wrong interval), --keys hold times, pan and framing, the interactive
// resolution, numbered screenshots and the availability check a backend switch makes first.
#ifdef PRISM_HAVE_VIEWER

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/test_support.h"
#include "viewer/backend_check.h"
#include "viewer/camera_controls.h"
#include "viewer/held_keys.h"
#include "viewer/interactive_scale.h"
#include "viewer/key_script.h"
#include "viewer/screenshot_names.h"

namespace {

using prism::viewer::FlyKey;
using prism::viewer::HeldKeys;

TEST(ViewerHeldKeys, HeldTimeIsCountedBetweenUpdatesWhateverTheFrameRate) {
    HeldKeys keys;
    keys.press(FlyKey::Forward, 10.0);
    // Updates at uneven intervals (slow and fast frames): each gets exactly the time since the previous one.
    EXPECT_NEAR(keys.collect(10.5).z, 0.5f, 1e-6f);
    EXPECT_NEAR(keys.collect(10.51).z, 0.01f, 1e-6f);
    EXPECT_NEAR(keys.collect(11.0).z, 0.49f, 1e-6f);
    keys.release(FlyKey::Forward, 11.2);
    EXPECT_NEAR(keys.collect(12.0).z, 0.2f, 1e-6f);  // only until the release
    EXPECT_EQ(keys.collect(13.0), glm::vec3(0.0f));
    EXPECT_FALSE(keys.any_down());
}

TEST(ViewerHeldKeys, TapsBetweenUpdatesCountAndRepeatsDoNot) {
    HeldKeys keys;
    keys.press(FlyKey::Left, 1.0);
    keys.press(FlyKey::Left, 1.05);  // key repeat: ignored
    keys.release(FlyKey::Left, 1.1);
    keys.press(FlyKey::Left, 1.3);
    keys.release(FlyKey::Left, 1.4);
    keys.release(FlyKey::Up, 1.4);  // a release of a key that is up: ignored
    glm::vec3 held = keys.collect(2.0);
    EXPECT_NEAR(held.x, -0.2f, 1e-6f);  // left is -x
    EXPECT_EQ(held.y, 0.0f);
}

TEST(ViewerHeldKeys, OppositeKeysCancelAndAxesAreSigned) {
    HeldKeys keys;
    keys.press(FlyKey::Forward, 0.0);
    keys.press(FlyKey::Back, 0.0);
    keys.press(FlyKey::Up, 0.0);
    keys.press(FlyKey::Right, 0.5);
    glm::vec3 held = keys.collect(1.0);
    EXPECT_NEAR(held.z, 0.0f, 1e-6f);
    EXPECT_NEAR(held.y, 1.0f, 1e-6f);
    EXPECT_NEAR(held.x, 0.5f, 1e-6f);
    keys.release_all(1.5);
    EXPECT_FALSE(keys.any_down());
    EXPECT_NEAR(keys.collect(3.0).y, 0.5f, 1e-6f);
}

TEST(ViewerKeys, FlyKeysTakeAHoldTime) {
    auto script = prism::viewer::parse_key_script("4:W:1.5,0:s,2:F,2:h,2:F1,3:L");
    ASSERT_EQ(script.size(), 6u);
    EXPECT_EQ(script[0].action, prism::viewer::Action::FlyBack);
    EXPECT_DOUBLE_EQ(script[0].hold_seconds, prism::viewer::kScriptedTapSeconds);
    EXPECT_EQ(script[1].action, prism::viewer::Action::FrameScene);
    EXPECT_EQ(script[2].action, prism::viewer::Action::ToggleHelp);
    EXPECT_EQ(script[3].action, prism::viewer::Action::ToggleHelp);
    EXPECT_EQ(script[4].action, prism::viewer::Action::Reload);
    EXPECT_EQ(script[5].action, prism::viewer::Action::FlyForward);
    EXPECT_DOUBLE_EQ(script[5].hold_seconds, 1.5);
    FlyKey key;
    ASSERT_TRUE(prism::viewer::fly_key_for(script[5].action, &key));
    EXPECT_EQ(key, FlyKey::Forward);
    EXPECT_FALSE(prism::viewer::fly_key_for(prism::viewer::Action::Reload, &key));
    for (const char* bad : {"0:M:1", "0:W:0", "0:W:-1", "0:W:x", "0:W:", "0:W:5000"}) {
        try {
            prism::viewer::parse_key_script(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const prism::Error& e) {
            EXPECT_EQ(std::string(e.what()).rfind("--keys: ", 0), 0u) << e.what();
        }
    }
}

TEST(ViewerKeys, ExposureAndToneMapKeys) {
    auto script = prism::viewer::parse_key_script("0:[,1:],2:t");
    ASSERT_EQ(script.size(), 3u);
    EXPECT_EQ(script[0].action, prism::viewer::Action::ExposureDown);
    EXPECT_EQ(script[1].action, prism::viewer::Action::ExposureUp);
    EXPECT_EQ(script[2].action, prism::viewer::Action::ToggleToneMap);
}

prism::Camera camera_at(glm::vec3 position, glm::vec3 target) {
    prism::Camera camera;
    camera.position = position;
    camera.target = target;
    camera.vertical_fov_degrees = 60.0f;
    return camera;
}

prism::Aabb box(glm::vec3 lower, glm::vec3 upper) {
    prism::Aabb bounds;
    bounds.grow(lower);
    bounds.grow(upper);
    return bounds;
}

TEST(ViewerCamera, FlySpeedIsATenthOfTheSceneDiagonalPerSecond) {
    prism::viewer::CameraControls controls(camera_at({0, 0, 10}, {0, 0, 0}));
    controls.set_scene_bounds(box({0, 0, 0}, {3, 4, 0}));  // diagonal 5
    EXPECT_NEAR(controls.fly_speed(), 0.5f, 1e-6f);
    controls.fly_for({0.0f, 0.0f, 2.0f});  // 2 s forward (-z)
    EXPECT_NEAR(controls.camera().position.z, 9.0f, 1e-5f);
    EXPECT_NEAR(controls.camera().target.z, -1.0f, 1e-5f);
    controls.set_scene_bounds(box({0, 0, 0}, {30, 40, 0}));  // ten times the scene: ten times the speed
    EXPECT_NEAR(controls.fly_speed(), 5.0f, 1e-5f);
    controls.set_scene_bounds(prism::Aabb{});  // no geometry: a speed still
    EXPECT_GT(controls.fly_speed(), 0.0f);
}

TEST(ViewerCamera, PanKeepsThePointAtTheTargetDepthUnderThePointer) {
    prism::viewer::CameraControls controls(camera_at({0, 0, 10}, {0, 0, 0}));
    // 60 degrees over 100 pixels at distance 10: the view is 2 * 10 * tan(30°) units high.
    float per_pixel = 2.0f * 10.0f * std::tan(glm::radians(30.0f)) / 100.0f;
    controls.pan({10.0f, 0.0f}, 100);  // dragging right: the scene follows, the eye goes left (-x)
    EXPECT_NEAR(controls.camera().position.x, -10.0f * per_pixel, 1e-4f);
    EXPECT_NEAR(controls.camera().target.x, -10.0f * per_pixel, 1e-4f);
    controls.pan({0.0f, 20.0f}, 100);  // dragging down: the eye goes up
    EXPECT_NEAR(controls.camera().position.y, 20.0f * per_pixel, 1e-4f);
    EXPECT_NEAR(glm::length(controls.camera().position - controls.camera().target), 10.0f, 1e-4f);
}

TEST(ViewerCamera, FrameSceneLooksAtTheBoundsFromWhereTheyFit) {
    prism::viewer::CameraControls controls(camera_at({0, 0, 1}, {0, 0, 0}));
    controls.set_scene_bounds(box({10, 10, 10}, {12, 12, 12}));
    controls.frame_scene(2.0f);  // wide: the vertical field of view is the narrower
    const prism::Camera& c = controls.camera();
    EXPECT_NEAR(glm::length(c.target - glm::vec3(11, 11, 11)), 0.0f, 1e-4f);
    float radius = std::sqrt(3.0f);
    EXPECT_NEAR(glm::length(c.position - c.target), radius / std::sin(glm::radians(30.0f)), 1e-3f);
    EXPECT_NEAR(c.position.x, 11.0f, 1e-4f);  // the viewing direction kept (-z)
    EXPECT_GT(c.position.z, c.target.z);
    controls.frame_scene(0.5f);  // tall: the horizontal field of view is narrower, so farther away
    EXPECT_GT(glm::length(controls.camera().position - controls.camera().target),
              radius / std::sin(glm::radians(30.0f)));
}

TEST(ViewerInteractiveScale, FixedAndAutomatic) {
    prism::viewer::InteractiveScale fixed("0.25", 30.0);
    fixed.record(100, 100, 1000.0);
    EXPECT_DOUBLE_EQ(fixed.moving_scale(), 0.25);
    EXPECT_FALSE(fixed.automatic());

    prism::viewer::InteractiveScale automatic("auto", 25.0);  // 40 ms a frame
    EXPECT_DOUBLE_EQ(automatic.moving_scale(), 1.0);
    automatic.record(200, 100, 160.0);  // four times too slow at full size: half the resolution per axis
    EXPECT_DOUBLE_EQ(automatic.moving_scale(), 0.5);
    automatic.record(100, 50, 30.0);  // between half the target and the target: kept
    EXPECT_DOUBLE_EQ(automatic.moving_scale(), 0.5);
    automatic.record(100, 50, 2.5);  // far faster than needed: back up, at most to full size
    EXPECT_DOUBLE_EQ(automatic.moving_scale(), 1.0);
    automatic.record(200, 100, 100000.0);  // never below 1/8
    EXPECT_DOUBLE_EQ(automatic.moving_scale(), 0.125);

    EXPECT_EQ(prism::viewer::InteractiveScale::scaled(1920, 0.5), 960u);
    EXPECT_EQ(prism::viewer::InteractiveScale::scaled(40, 0.125), 8u);  // at least 8 pixels
    EXPECT_EQ(prism::viewer::InteractiveScale::scaled(4, 0.5), 4u);     // never above full size
}

TEST(ViewerInteractiveScale, BadSettingsNameTheOption) {
    for (const char* bad : {"0", "1.5", "-0.5", "half", ""}) {
        try {
            prism::viewer::InteractiveScale scale(bad, 30.0);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const prism::Error& e) {
            EXPECT_NE(std::string(e.what()).find("--interactive-scale"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW(prism::viewer::InteractiveScale("auto", 0.0), prism::Error);
    EXPECT_THROW(prism::viewer::InteractiveScale("auto", -30.0), prism::Error);
}

TEST(ViewerScreenshots, NumberedNamesNeverOverwrite) {
    std::filesystem::path dir = prism::test::temp_dir("viewer-screenshot-names");
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    EXPECT_EQ(prism::viewer::next_screenshot_path(dir).filename(), "prism-view-0001.png");
    std::ofstream(dir / "prism-view-0001.png") << "x";
    std::ofstream(dir / "prism-view-0002.png") << "x";
    EXPECT_EQ(prism::viewer::next_screenshot_path(dir).filename(), "prism-view-0003.png");
}

TEST(ViewerBackendCheck, SaysWhyBeforeAnythingIsBuilt) {
    EXPECT_EQ(prism::viewer::why_backend_unavailable("cpu"), "");
    EXPECT_EQ(prism::viewer::why_backend_unavailable("cpu-ref"), "");
    EXPECT_EQ(prism::viewer::why_backend_unavailable("metal"), "not compiled into this build");
    EXPECT_NE(prism::viewer::why_backend_unavailable("cpu:no-such-device-here"), "");
}

}  // namespace

#endif  // PRISM_HAVE_VIEWER

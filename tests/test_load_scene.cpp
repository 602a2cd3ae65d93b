// load_scene: dispatch by name and extension, the defaults a bare model gets, and frame_scene.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "core/util/error.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace prism {
namespace {

std::string error_message(const std::string& spec) {
    return test::error_message([&] { (void)load_scene(spec); });
}

TEST(LoadScene, MissingAndUnsupportedFiles) {
    std::string missing = (test::temp_dir("load_scene") / "nothing.glb").string();
    EXPECT_EQ(error_message(missing), missing + ": no such file");
    std::string unknown = test::write_file("model.xyz", "1 2 3\n").string();
    EXPECT_EQ(error_message(unknown), unknown + ": unsupported scene format");
}

TEST(LoadScene, ExtensionsAreCaseInsensitive) {
    std::filesystem::path upper = test::temp_dir("load_scene") / "BOX.GLB";
    std::filesystem::copy_file(test::scene("gltf/Box/Box.glb"), upper,
                               std::filesystem::copy_options::overwrite_existing);
    EXPECT_EQ(load_scene(upper.string()).triangle_count(), 12u);
}

TEST(LoadScene, BareModelGetsMaterialLightsSkyAndCamera) {
    LoadOptions options;
    options.data_dir = test::scenes_dir();
    Scene scene = load_scene(test::scene("stanford/bunny_res2.ply").string(), options);
    EXPECT_EQ(scene.source, test::scene("stanford/bunny_res2.ply").string());
    EXPECT_EQ(scene.triangle_count(), 16301u);
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].diffuse, glm::vec3(0.8f));
    ASSERT_EQ(scene.lights.size(), 2u);
    EXPECT_EQ(scene.lights[0].type, LightType::Directional);
    EXPECT_EQ(scene.lights[1].type, LightType::Point);
    EXPECT_EQ(scene.environment.kind, EnvironmentKind::CubeMap);  // the Miramar sky is in data_dir
    EXPECT_EQ(scene.ambient_light, glm::vec3(0.1f));
    EXPECT_FALSE(scene.has_camera);  // placed by frame_scene, not by the file

    // Without the data directory the sky is a constant colour.
    options.data_dir = test::temp_dir("no_sky");
    EXPECT_EQ(load_scene(test::scene("stanford/bunny_res2.ply").string(), options).environment.kind,
              EnvironmentKind::Constant);
}

TEST(LoadScene, FrameSceneFitsTheBoundingSphere) {
    Scene scene;
    Mesh mesh;
    mesh.positions = {{-1, -1, -1}, {1, 1, 1}, {1, -1, 1}};
    mesh.triangles = {{0, 1, 2}};
    mesh.triangle_materials = {0};
    scene.meshes.push_back(mesh);
    Instance instance;
    instance.transform =
        glm::translate(glm::mat4(1.0f), glm::vec3(10, 0, 0)) * glm::scale(glm::mat4(1.0f), glm::vec3(2));
    scene.instances.push_back(instance);
    frame_scene(scene);
    EXPECT_EQ(scene.camera.target, glm::vec3(10, 0, 0));
    float radius = std::sqrt(3.0f * 4.0f * 4.0f) * 0.5f;  // half the diagonal of the 4x4x4 world box
    float half_fov = glm::radians(scene.camera.vertical_fov_degrees) * 0.5f;
    float distance = glm::length(scene.camera.position - scene.camera.target);
    EXPECT_NEAR(distance, radius / std::sin(half_fov), 1e-3f);
    // Seen from the camera, the sphere around the box subtends exactly the vertical field of view.
    EXPECT_NEAR(std::asin(radius / distance), half_fov, 1e-4f);
}

TEST(LoadScene, GltfCameraIsKept) {
    Scene scene = load_scene(test::scene("gltf/Cameras/Cameras.gltf").string());
    EXPECT_TRUE(scene.has_camera);
    EXPECT_NEAR(scene.camera.position.z, 3.0f, 1e-6f);
}

}  // namespace
}  // namespace prism

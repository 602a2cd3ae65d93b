// docs/scene-format.md shows complete scene files; each of its ```json blocks must load with Prism's scene loader
// as the page says: saved in the repository root, where ../shared/scenes holds the assets. The page must also
// show every key the loader accepts, so a key added to core/loaders/load_scene_json.cpp without documentation fails
// here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/util/error.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace {

namespace fs = std::filesystem;

struct Example {
    int line = 0;  // where the block starts in the page, for messages
    std::string text;
};

std::string page_text() {
    std::ifstream in(fs::path(PRISM_SOURCE_DIR) / "docs/scene-format.md");
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::vector<Example> json_examples(const std::string& page) {
    std::vector<Example> examples;
    std::istringstream lines(page);
    int number = 0;
    bool inside = false;
    for (std::string line; std::getline(lines, line);) {
        ++number;
        if (!inside && line == "```json") {
            inside = true;
            examples.push_back({number, ""});
        } else if (inside && line.rfind("```", 0) == 0) {
            inside = false;
        } else if (inside) {
            examples.back().text += line + "\n";
        }
    }
    return examples;
}

// <dir>/repo/ stands for the repository root and <dir>/shared/scenes for the asset folder beside it.
fs::path example_folder() {
    fs::path dir = prism::test::temp_dir("scene-format-examples");
    fs::create_directories(dir / "repo");
    fs::create_directories(dir / "shared");
    fs::path link = dir / "shared" / "scenes";
    if (!fs::exists(link)) fs::create_directory_symlink(fs::absolute(prism::test::scenes_dir()), link);
    // The examples may name the repository's own docs/examples (an animated glTF written for them).
    fs::path docs = dir / "repo" / "docs";
    if (!fs::exists(docs)) fs::create_directory_symlink(fs::path(PRISM_SOURCE_DIR) / "docs", docs);
    return dir / "repo";
}

TEST(DocsSceneFormat, EveryJsonExampleLoads) {
    std::vector<Example> examples = json_examples(page_text());
    ASSERT_GE(examples.size(), 15u) << "docs/scene-format.md lost its examples, or the ```json fence changed";
    fs::path folder = example_folder();
    for (size_t i = 0; i < examples.size(); ++i) {
        fs::path file = folder / ("example-line-" + std::to_string(examples[i].line) + ".json");
        std::ofstream(file) << examples[i].text;
        std::string error;
        try {
            // The examples name the shared assets beside the repository, outside the scene's folder: as the page
            // says, that takes --allow-any-path.
            prism::LoadOptions options;
            options.allow_any_path = true;
            prism::Scene scene = prism::load_scene(file.string(), options);
            EXPECT_GT(scene.triangle_count(), 0u);
        } catch (const prism::Error& e) {
            error = e.what();
        }
        EXPECT_EQ(error, "") << "docs/scene-format.md, the example at line " << examples[i].line;
    }
}

// Every key core/loaders/load_scene_json.cpp reads, and every texture mode: each appears in an example and in the
// page's tables (as `key`).
TEST(DocsSceneFormat, EveryKeyIsDocumentedAndShown) {
    const std::string page = page_text();
    std::string all_examples;
    for (const Example& example : json_examples(page)) all_examples += example.text;
    // clang-format off
    const char* keys[] = {"objects",  "materials", "camera",       "lights",        "ambient",   "environment",
                          "position", "target",    "up",           "fov",           "type",      "direction",
                          "color",    "intensity", "cubemap",      "equirect",      "diffuse",   "use_vertex_colors",
                          "textures", "specular",  "reflectivity", "transmittance", "ior",       "thickness",
                          "fresnel",  "bias",      "scale",        "power",         "emissive",  "file",
                          "mode",     "env_color", "uv_set",       "material",      "transform", "matrix",
                          "name",     "translate", "rotate",       "range",         "inner_cone_degrees",
                          "outer_cone_degrees",        "spin",         "animation"};
    // clang-format on
    for (const char* key : keys) {
        // Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string here.
        std::string quoted = "\"", cell = "| `";
        quoted.append(key).append("\":");
        cell.append(key).append("` |");
        EXPECT_NE(all_examples.find(quoted), std::string::npos) << key << " in no example";
        EXPECT_NE(page.find(cell), std::string::npos) << key << " in no table";
    }
    // The two forms of `rotate` are spelled out in its table row.
    size_t row = page.find("| `rotate` |");
    ASSERT_NE(row, std::string::npos);
    std::string rotate_row = page.substr(row, page.find('\n', row) - row);
    for (const char* key : {"axis", "degrees", "quaternion"}) {
        EXPECT_NE(all_examples.find("\"" + std::string(key) + "\":"), std::string::npos) << key << " in no example";
        EXPECT_NE(rotate_row.find("\"" + std::string(key) + "\":"), std::string::npos) << key << " not in its row";
    }
    for (const char* mode : {"replace", "decal", "modulate", "blend"})
        EXPECT_NE(all_examples.find("\"mode\": \"" + std::string(mode) + "\""), std::string::npos) << mode;
    EXPECT_NE(all_examples.find("\"type\": \"directional\""), std::string::npos);
    EXPECT_NE(all_examples.find(".hdr\""), std::string::npos) << "no HDR environment example";
}

}  // namespace

// The documentation points only at things that exist: every relative link in README.md and docs/ (with its #anchor,
// matched against the target's headings as GitHub names them), and every mention of a docs/ page or another .md file
// in the docs, the sources, the build files and the scripts. A renamed or never-written page fails here, not in a
// reader's browser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path kRoot = PRISM_SOURCE_DIR;

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string relative_name(const fs::path& path) { return fs::relative(path, kRoot).string(); }

std::vector<fs::path> markdown_files() {
    std::vector<fs::path> files = {kRoot / "README.md"};
    for (const auto& entry : fs::recursive_directory_iterator(kRoot / "docs"))
        if (entry.is_regular_file() && entry.path().extension() == ".md") files.push_back(entry.path());
    return files;
}

// Every file of the project that may name a page: sources, shaders, build files, scripts, docs.
std::vector<fs::path> project_text_files() {
    const std::set<std::string> extensions = {".md", ".h",  ".cpp", ".cu",    ".cl",   ".comp",
                                              ".sh", ".py", ".txt", ".cmake", ".json", ".in"};
    std::vector<fs::path> files;
    for (const char* name : {"README.md", "CMakeLists.txt", "CMakePresets.json"}) files.push_back(kRoot / name);
    for (const char* folder : {".ci", "apps", "backends", "bench", "cmake", "core", "docs", "fuzz", "kernels",
                               "scripts", "shaders", "tests", "viewer"}) {
        if (!fs::is_directory(kRoot / folder)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(kRoot / folder)) {
            if (!entry.is_regular_file()) continue;
            const fs::path& path = entry.path();
            if (path.parent_path().filename() == "results") continue;  // measured data, not prose
            bool script = path.extension().empty() && path.parent_path().filename() == ".ci";
            if (extensions.count(path.extension().string()) || script) files.push_back(path);
        }
    }
    return files;
}

// GitHub's anchor for a heading: lower case, punctuation other than '-' and '_' dropped, spaces to '-'.
std::string anchor_of(const std::string& heading) {
    std::string anchor;
    for (unsigned char c : heading) {
        if (std::isalnum(c) || c == '-' || c == '_')
            anchor += static_cast<char>(std::tolower(c));
        else if (c == ' ')
            anchor += '-';
    }
    return anchor;
}

std::set<std::string> anchors_in(const fs::path& markdown) {
    std::set<std::string> anchors;
    std::istringstream lines(read_text(markdown));
    bool in_code = false;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("```", 0) == 0) in_code = !in_code;
        if (in_code || line.empty() || line[0] != '#') continue;
        size_t text = line.find_first_not_of('#');
        if (text == std::string::npos) continue;
        anchors.insert(anchor_of(line.substr(line.find_first_not_of(' ', text))));
    }
    return anchors;
}

// The text outside fenced code blocks: commands and JSON shown there are not links.
std::string prose_of(const std::string& markdown) {
    std::istringstream lines(markdown);
    std::string prose;
    bool in_code = false;
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("```", 0) == 0) {
            in_code = !in_code;
            continue;
        }
        if (!in_code) prose += line + "\n";
    }
    return prose;
}

TEST(DocsLinks, RelativeLinksInReadmeAndDocsResolve) {
    const std::regex link(R"(\]\(([^)\s]+)\))");
    size_t checked = 0;
    for (const fs::path& file : markdown_files()) {
        std::string prose = prose_of(read_text(file));
        for (std::sregex_iterator it(prose.begin(), prose.end(), link), end; it != end; ++it) {
            std::string target = (*it)[1];
            if (target.find("://") != std::string::npos || target.rfind("mailto:", 0) == 0) continue;
            size_t hash = target.find('#');
            std::string path_part = target.substr(0, hash);
            std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
            fs::path resolved = path_part.empty() ? file : file.parent_path() / path_part;
            ++checked;
            ASSERT_TRUE(fs::exists(resolved))
                << relative_name(file) << ": link '" << target << "': no " << resolved.lexically_normal();
            if (!anchor.empty() && resolved.extension() == ".md") {
                EXPECT_TRUE(anchors_in(resolved).count(anchor))
                    << relative_name(file) << ": link '" << target << "': no heading with anchor #" << anchor << " in "
                    << relative_name(resolved);
            }
        }
    }
    EXPECT_GT(checked, 10u) << "the link pattern found almost nothing: is it still right?";
}

// "docs/<page>.md" anywhere must exist; a bare "<page>.md" must be a page of docs/ (or the repository root), or of
// the markdown file's own folder. Paths that leave the repository ("../shared/...") are not this project's pages.
TEST(DocsLinks, EveryMentionedPageExists) {
    const std::regex mention(R"((^|[^\w/.-])((docs/)?[\w.-]+\.md)\b)");
    size_t checked = 0;
    for (const fs::path& file : project_text_files()) {
        std::string text = read_text(file);
        for (std::sregex_iterator it(text.begin(), text.end(), mention), end; it != end; ++it) {
            std::string page = (*it)[2];
            ++checked;
            bool found = fs::exists(kRoot / page) || fs::exists(kRoot / "docs" / page) ||
                         (file.extension() == ".md" && fs::exists(file.parent_path() / page));
            EXPECT_TRUE(found) << relative_name(file) << " mentions " << page << ", which is not in the repository";
        }
    }
    EXPECT_GT(checked, 20u) << "the mention pattern found almost nothing: is it still right?";
}

TEST(DocsLinks, AnchorsFollowGithubHeadingIds) {
    EXPECT_EQ(anchor_of("Objects and instances"), "objects-and-instances");
    EXPECT_EQ(anchor_of("Fresnel bias, scale and power"), "fresnel-bias-scale-and-power");
    EXPECT_EQ(anchor_of("Prism scene files (`.json`)"), "prism-scene-files-json");
}

}  // namespace

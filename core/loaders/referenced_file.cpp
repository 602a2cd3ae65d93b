#include "core/loaders/referenced_file.h"

#include <system_error>

#include "core/image/image_io.h"
#include "core/util/input_file.h"
#include "core/util/scene_read_rules.h"

namespace prism {

std::filesystem::path find_referenced_file(const std::string& referring_file, const std::string& name,
                                           const std::filesystem::path& directory) {
    const std::filesystem::path path = find_file_case_insensitive(directory, name);
    if (path.empty()) {
        // find_file_case_insensitive finds regular files only: something else under the exact name is refused
        // here, after the folder rule.
        const std::filesystem::path exact = directory / name;
        std::error_code error;
        if (std::filesystem::exists(exact, error)) {
            check_scene_reference(referring_file, name, exact);
            require_regular_file(exact);
        }
        return {};
    }
    check_scene_reference(referring_file, name, path);
    return path;
}

}  // namespace prism

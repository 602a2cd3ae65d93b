#include "core/util/build_info.h"

#include "git_commit.h"  // generated at build time by cmake/PrismGitCommit.cmake

namespace prism {
const char* build_commit() { return PRISM_GIT_COMMIT; }
const char* build_type() { return PRISM_BUILD_TYPE; }
}  // namespace prism

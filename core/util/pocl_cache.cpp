#include "core/util/pocl_cache.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

#include <unistd.h>

namespace prism {
namespace {

namespace fs = std::filesystem;

// PoCL 3.1's own choice (pocl_cache.c).
fs::path pocl_cache_dir() {
    if (const char* dir = std::getenv("POCL_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "pocl" / "kcache";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "pocl" / "kcache";
    return {};
}

// Whether `dir` exists as a writable folder or could be created, judged without creating anything (a machine
// without PoCL gets no folders from Prism). access() sees read-only mounts even for root; a path beneath a
// regular file fails for everyone.
bool usable(const fs::path& dir, std::string& why) {
    std::error_code error;
    fs::path existing = dir;
    while (!existing.empty() && !fs::exists(existing, error)) {
        if (existing == existing.parent_path()) break;
        existing = existing.parent_path();
    }
    if (existing.empty()) existing = ".";
    if (!fs::is_directory(existing, error)) {
        why = existing.string() + " is not a folder";
        return false;
    }
    if (::access(existing.c_str(), W_OK | X_OK) != 0) {
        why = existing.string() + ": " + std::strerror(errno);
        return false;
    }
    return true;
}

std::string fallback_to_private_dir() {
    const fs::path dir = pocl_cache_dir();
    std::string why;
    if (dir.empty() || usable(dir, why)) return "";
    std::error_code error;
    // mkdtemp: a fresh 0700 folder per run, so no other user can plant kernels in it; not reused, not cached.
    std::string pattern = (fs::temp_directory_path(error) / "prism-pocl-XXXXXX").string();
    if (error || !::mkdtemp(pattern.data())) return "";  // nothing better to offer: PoCL says what failed
    ::setenv("POCL_CACHE_DIR", pattern.c_str(), 1);
    static const std::string created = pattern;
    std::atexit([] {
        std::error_code ignored;
        fs::remove_all(created, ignored);
    });
    std::string warning = "prism: warning: PoCL cannot use its kernel cache " + dir.string() + " (" + why +
                          "); using " + pattern + " for this run";
    std::fprintf(stderr, "%s\n", warning.c_str());
    return warning;
}

}  // namespace

std::string ensure_pocl_cache_dir() {
    static std::once_flag once;
    static std::string warning;
    std::call_once(once, [] { warning = fallback_to_private_dir(); });
    return warning;
}

}  // namespace prism

// Writes a whole output file or nothing: bytes go to "<path>.tmp-<pid>" and are renamed into place, so a failed
// run never leaves a partial file where the user expects a result.
#pragma once

#include <filesystem>
#include <string_view>

#include "core/util/non_copyable.h"

namespace prism {

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

// A file written now under its temporary name and moved into place by commit(), or removed when dropped
// uncommitted: a run writing several outputs stages all but the last, writes the last, then commits, so its
// outputs appear together or not at all.
class StagedOutput : private NonCopyable {
public:
    StagedOutput(std::filesystem::path path, std::string_view bytes);
    ~StagedOutput();
    void commit();

private:
    std::filesystem::path path_, temporary_;
    bool committed_ = false;
};

}  // namespace prism

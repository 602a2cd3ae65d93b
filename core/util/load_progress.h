// How far a scene load has come, for the progress line of `prism render`, `view` and `bench` (apps/progress.h):
// loaders report the fraction of their own work done, and a loader that runs others (a scene file's objects, a
// gzip stream before its PLY body) gives each a share of its own range. Thread-local like SceneReadScope, so the
// loaders need no extra parameter and split-render workers loading side by side each report to their own line.
#pragma once

#include <functional>

#include "core/util/non_copyable.h"

namespace prism {

using LoadProgressCallback = std::function<void(double fraction)>;

// Reports of this thread go to `callback` (0 to 1) while the scope lives.
class LoadProgressScope : private NonCopyable {
public:
    explicit LoadProgressScope(LoadProgressCallback callback);
    ~LoadProgressScope();

private:
    LoadProgressCallback callback_;
    const LoadProgressCallback* previous_;
};

// Within this scope, a report of f in [0, 1] stands for begin + f * (end - begin) of the enclosing range.
class LoadProgressShare : private NonCopyable {
public:
    LoadProgressShare(double begin, double end);
    ~LoadProgressShare();

private:
    double previous_offset_, previous_scale_;
};

// A loader's news: `fraction` of its (share of the) work is done. Nothing happens outside a LoadProgressScope.
void report_load_progress(double fraction);

}  // namespace prism

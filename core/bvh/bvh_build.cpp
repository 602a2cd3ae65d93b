// BVH builders into the intermediate tree: binned SAH and the seed's median split (thesis 6.2.1, Algorithm 6-1).
//
// Determinism: every split decision is taken by one thread from values that do not depend on how the work was
// divided. Parallel passes only bin or bound primitives, and their partial results merge with min/max and integer
// sums, which are exact and order-independent; partitions run sequentially. So the tree is the same for any
// thread count, and images are bit-identical run to run.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>

#include "core/bvh/bvh.h"
#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism {

namespace {

constexpr uint32_t kTaskThreshold = 4096;              // subtrees larger than this may run on another thread
constexpr uint32_t kParallelPassThreshold = 1u << 16;  // binning/bounding passes this large are split in chunks
constexpr uint32_t kPassChunk = 1u << 15;
// Below this depth every split is an index median, so no input can make the tree deeper than
// kBalancedDepth + log2(primitives): with 2^24 primitives that still fits RT_BVH_STACK_SIZE (64). Real meshes never
// get near it (the bunny's SAH tree is ~25 deep).
constexpr uint32_t kBalancedDepth = 40;
constexpr uint32_t kMaxBins = 256;

// Threads that may still be started, shared by subtree tasks and chunked passes so the total stays at `threads`.
class ThreadBudget {
public:
    explicit ThreadBudget(int spare) : spare_(spare) {}
    int acquire(int wanted) {
        int current = spare_.load();
        while (current > 0 && wanted > 0) {
            int taken = std::min(current, wanted);
            if (spare_.compare_exchange_weak(current, current - taken)) return taken;
        }
        return 0;
    }
    void release(int count) { spare_ += count; }

private:
    std::atomic<int> spare_;
};

// Runs body(begin, end, part) over `parts` equal chunks of [begin, end), parts - 1 of them on helper threads.
template <class Body>
void run_in_parts(uint32_t begin, uint32_t end, int parts, const Body& body) {
    std::vector<std::thread> helpers;
    uint32_t size = end - begin;
    for (int part = 1; part < parts; ++part) {
        uint32_t b = begin + uint32_t(uint64_t(size) * part / parts);
        uint32_t e = begin + uint32_t(uint64_t(size) * (part + 1) / parts);
        helpers.emplace_back([&body, b, e, part] { body(b, e, part); });
    }
    body(begin, begin + uint32_t(uint64_t(size) / parts), 0);
    for (auto& helper : helpers) helper.join();
}

struct RangeBounds {
    Aabb box;        // of the primitive bounds
    Aabb centroids;  // of the primitive centroids
    void grow(const RangeBounds& other) {
        box.grow(other.box);
        centroids.grow(other.centroids);
    }
};

// One primitive in the working array. Builders move these (not indices into the caller's bounds) so every pass
// reads memory in order.
struct Reference {
    glm::vec3 lower;
    uint32_t primitive;
    glm::vec3 upper;
    uint32_t unused;
    // Always computed the same way, so bins and partitions see identical values.
    glm::vec3 centroid() const { return 0.5f * (lower + upper); }
};

struct Bin {
    Aabb box;
    uint32_t count = 0;
    void grow(const Bin& other) {
        box.grow(other.box);
        count += other.count;
    }
};

// Maps a centroid coordinate to its bin on one axis; the same function counts and partitions, so both agree.
struct AxisBinning {
    float origin = 0.0f;
    float scale = 0.0f;  // 0: the axis cannot be binned (no centroid extent)
    uint32_t bins = 0;
    uint32_t bin(float coordinate) const {
        float position = (coordinate - origin) * scale;
        return std::min(uint32_t(std::max(position, 0.0f)), bins - 1);
    }
};

struct Split {
    int axis = -1;  // -1: none found
    uint32_t last_left_bin = 0;
    float cost = std::numeric_limits<float>::infinity();  // sum of area * count over both sides
};

struct Task {
    uint32_t begin, end;
    RangeBounds bounds;
    uint32_t depth;  // root = 0
};

class TreeBuilder {
public:
    TreeBuilder(std::span<const Aabb> bounds, const BvhBuildOptions& options, BvhTree& tree, int threads,
                const BvhProgress& progress)
        : options_(options), tree_(tree), budget_(threads - 1), progress_(progress) {
        max_leaf_ = options.max_leaf_size;
        if (options.layout == BvhLayout::Escape) max_leaf_ = std::min<uint32_t>(max_leaf_, 255u);
        // The wide layout packs a leaf's count in 3 bits and tests its primitives four at a time: its SAH counts
        // blocks of four (as Embree does).
        if (options.layout == BvhLayout::Wide) max_leaf_ = std::min<uint32_t>(max_leaf_, RT_WIDE_LEAF_MAX);
        leaf_block_ = options.layout == BvhLayout::Wide ? 4u : 1u;
        for (uint32_t i = 0; i < bounds.size(); ++i)
            if (bvh_usable_bounds(bounds[i])) references_.push_back({bounds[i].lower, i, bounds[i].upper, 0});
    }

    void build() {
        auto& arena = new_arena();
        uint32_t count = uint32_t(references_.size());
        if (count == 0) {
            arena.emplace_back();  // one leaf, count 0, empty box
            tree_.root = &arena.back();
            tree_.node_count = 1;
            tree_.depth = 1;
            return;
        }
        Task root{0, count, bounds_of(0, count), 0};
        tree_.root = build_subtree(root, arena);
        tree_.node_count = node_count_.load();
        tree_.depth = depth_.load();
        tree_.primitive_order.resize(count);
        for (uint32_t i = 0; i < count; ++i) tree_.primitive_order[i] = references_[i].primitive;
    }

private:
    std::deque<BvhBuildNode>& new_arena() {
        std::lock_guard lock(arenas_mutex_);
        return tree_.arenas.emplace_back();
    }

    int helpers_for(uint32_t count) {
        if (count < kParallelPassThreshold) return 0;
        return budget_.acquire(int(count / kPassChunk) - 1);
    }

    RangeBounds bounds_of(uint32_t begin, uint32_t end) {
        int helpers = helpers_for(end - begin);
        std::vector<RangeBounds> parts(helpers + 1);
        run_in_parts(begin, end, helpers + 1, [&](uint32_t b, uint32_t e, int part) {
            RangeBounds bounds;
            for (uint32_t i = b; i < e; ++i) {
                const Reference& reference = references_[i];
                bounds.box.grow(Aabb{reference.lower, reference.upper});
                bounds.centroids.grow(reference.centroid());
            }
            parts[part] = bounds;
        });
        budget_.release(helpers);
        RangeBounds total;
        for (const auto& part : parts) total.grow(part);
        return total;
    }

    const BvhBuildNode* build_subtree(const Task& task, std::deque<BvhBuildNode>& arena) {
        BvhBuildNode& node = arena.emplace_back();
        node_count_.fetch_add(1, std::memory_order_relaxed);
        node.box = task.bounds.box;
        uint32_t depth = task.depth + 1;
        for (uint32_t seen = depth_.load(); seen < depth && !depth_.compare_exchange_weak(seen, depth);) {
        }

        uint32_t count = task.end - task.begin;
        Task left, right;
        if (!split(task, left, right)) {
            node.first = task.begin;
            node.count = count;
            if (progress_) report_leaf(count);
            return &node;
        }

        bool parallel = left.end - left.begin > kTaskThreshold && right.end - right.begin > kTaskThreshold &&
                        budget_.acquire(1) == 1;
        if (parallel) {
            // The worker gives its thread back as soon as it is done, so the other side can split it again.
            std::thread worker([&] {
                node.children[0] = build_subtree(left, new_arena());
                budget_.release(1);
            });
            node.children[1] = build_subtree(right, arena);
            worker.join();
        } else {
            node.children[0] = build_subtree(left, arena);
            node.children[1] = build_subtree(right, arena);
        }
        return &node;
    }

    float blocks(uint32_t count) const { return float((count + leaf_block_ - 1) / leaf_block_); }

    // Decides leaf or split; on a split, partitions the references and fills both child tasks.
    bool split(const Task& task, Task& left, Task& right) {
        uint32_t count = task.end - task.begin;
        if (count <= 1) return false;
        if (task.depth >= kBalancedDepth) return count > max_leaf_ && split_at_index_median(task, left, right);
        if (options_.method == BvhMethod::Median) return count > max_leaf_ && split_at_box_median(task, left, right);

        Split best = find_sah_split(task);
        if (count <= max_leaf_) {
            // Small enough for a leaf: split only where the SAH says it pays.
            if (best.axis < 0) return false;
            float area = task.bounds.box.half_area();
            float leaf_cost = options_.intersection_cost * area * blocks(count);
            float split_cost = options_.traversal_cost * area + options_.intersection_cost * best.cost;
            if (leaf_cost <= split_cost) return false;
        }
        if (best.axis < 0) return split_at_index_median(task, left, right);  // all centroids equal

        AxisBinning binning = binning_for(task.bounds.centroids, best.axis);
        int axis = best.axis;
        return partition(task, left, right, [&](const Reference& reference) {
            return binning.bin(reference.centroid()[axis]) <= best.last_left_bin;
        });
    }

    // Moves the references that satisfy goes_left to the front, measuring both sides on the way.
    template <class Predicate>
    bool partition(const Task& task, Task& left, Task& right, const Predicate& goes_left) {
        RangeBounds left_bounds, right_bounds;
        uint32_t i = task.begin, j = task.end;
        while (i < j) {
            const Reference& reference = references_[i];
            if (goes_left(reference)) {
                left_bounds.box.grow(Aabb{reference.lower, reference.upper});
                left_bounds.centroids.grow(reference.centroid());
                ++i;
            } else {
                right_bounds.box.grow(Aabb{reference.lower, reference.upper});
                right_bounds.centroids.grow(reference.centroid());
                std::swap(references_[i], references_[--j]);
            }
        }
        if (i == task.begin || i == task.end) return split_at_index_median(task, left, right);
        left = {task.begin, i, left_bounds, task.depth + 1};
        right = {i, task.end, right_bounds, task.depth + 1};
        return true;
    }

    AxisBinning binning_for(const Aabb& centroids, int axis) const {
        AxisBinning binning;
        binning.bins = options_.bins;
        binning.origin = centroids.lower[axis];
        float extent = centroids.upper[axis] - centroids.lower[axis];
        float scale = extent > 0.0f ? float(options_.bins) / extent : 0.0f;
        binning.scale = std::isfinite(scale) ? scale : 0.0f;
        return binning;
    }

    void bin_range(uint32_t begin, uint32_t end, const AxisBinning (&binnings)[3], Bin* bins) const {
        const uint32_t bin_count = options_.bins;
        for (uint32_t i = begin; i < end; ++i) {
            const Reference& reference = references_[i];
            glm::vec3 centroid = reference.centroid();
            for (int axis = 0; axis < 3; ++axis) {
                if (binnings[axis].scale == 0.0f) continue;
                Bin& bin = bins[axis * bin_count + binnings[axis].bin(centroid[axis])];
                bin.box.lower = glm::min(bin.box.lower, reference.lower);
                bin.box.upper = glm::max(bin.box.upper, reference.upper);
                bin.count++;
            }
        }
    }

    Split find_sah_split(const Task& task) {
        const uint32_t bin_count = options_.bins;
        AxisBinning binnings[3];
        for (int axis = 0; axis < 3; ++axis) binnings[axis] = binning_for(task.bounds.centroids, axis);

        // Reused per thread: a node's binning finishes before its children start.
        thread_local std::vector<Bin> bins;
        bins.assign(3 * bin_count, Bin{});
        int helpers = helpers_for(task.end - task.begin);
        if (helpers == 0) {
            bin_range(task.begin, task.end, binnings, bins.data());
        } else {
            std::vector<std::vector<Bin>> parts(helpers + 1, std::vector<Bin>(3 * bin_count));
            run_in_parts(task.begin, task.end, helpers + 1,
                         [&](uint32_t b, uint32_t e, int part) { bin_range(b, e, binnings, parts[part].data()); });
            budget_.release(helpers);
            for (const auto& part : parts)
                for (uint32_t i = 0; i < 3 * bin_count; ++i) bins[i].grow(part[i]);
        }

        Split best;
        float right_costs[kMaxBins];  // area * count of bins i.. on the right
        for (int axis = 0; axis < 3; ++axis) {
            if (binnings[axis].scale == 0.0f) continue;
            const Bin* axis_bins = &bins[axis * bin_count];
            // Empty bins are skipped: a split after one equals the split after the last non-empty bin before it,
            // which comes first and so wins the strict comparison anyway. Small nodes have mostly empty bins.
            Bin sum;
            float right_cost = 0.0f;
            for (uint32_t i = bin_count; i-- > 1;) {
                if (axis_bins[i].count != 0) {
                    sum.grow(axis_bins[i]);
                    right_cost = sum.box.half_area() * blocks(sum.count);
                }
                right_costs[i] = sum.count ? right_cost : -1.0f;
            }
            Bin left;
            for (uint32_t i = 0; i + 1 < bin_count; ++i) {
                if (axis_bins[i].count == 0) continue;
                left.grow(axis_bins[i]);
                if (right_costs[i + 1] < 0.0f) continue;
                float cost = left.box.half_area() * blocks(left.count) + right_costs[i + 1];
                if (cost < best.cost) best = {axis, i, cost};
            }
        }
        return best;
    }

    // Thesis Algorithm 6-1: pivot at the middle of the node box on an axis cycling x, y, z per level; primitives
    // go left when their centroid lies below it. An empty side falls back to the index median.
    // Primitives in leaves so far, reported when a whole percent more of them is placed (whichever thread crosses it).
    void report_leaf(uint32_t count) {
        const uint64_t total = references_.size();
        uint64_t placed = placed_.fetch_add(count, std::memory_order_relaxed) + count;
        uint32_t percent = uint32_t(placed * 100 / total);
        uint32_t reported = reported_percent_.load(std::memory_order_relaxed);
        if (percent > reported && reported_percent_.compare_exchange_strong(reported, percent))
            progress_(double(placed) / double(total));
    }

    bool split_at_box_median(const Task& task, Task& left, Task& right) {
        int axis = int(task.depth % 3);
        float pivot = task.bounds.box.center()[axis];
        return partition(task, left, right,
                         [&](const Reference& reference) { return reference.centroid()[axis] < pivot; });
    }

    bool split_at_index_median(const Task& task, Task& left, Task& right) {
        uint32_t mid = task.begin + (task.end - task.begin) / 2;
        left = {task.begin, mid, bounds_of(task.begin, mid), task.depth + 1};
        right = {mid, task.end, bounds_of(mid, task.end), task.depth + 1};
        return true;
    }

    const BvhBuildOptions& options_;
    BvhTree& tree_;
    ThreadBudget budget_;
    uint32_t max_leaf_ = 4;
    std::vector<Reference> references_;
    std::mutex arenas_mutex_;
    std::atomic<uint32_t> node_count_{0};
    std::atomic<uint32_t> depth_{0};
    uint32_t leaf_block_ = 1;
    const BvhProgress& progress_;
    std::atomic<uint64_t> placed_{0};
    std::atomic<uint32_t> reported_percent_{0};
};

int resolve_threads(uint32_t requested) {
    if (requested != 0) return int(std::min<uint32_t>(requested, 1024));
    return int(std::max(1u, std::thread::hardware_concurrency()));
}

void check_options(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options) {
    if (options.max_leaf_size == 0) throw Error("BVH build: max_leaf_size must be at least 1");
    if (options.bins < 2 || options.bins > kMaxBins)
        throw Error("BVH build: bins must be between 2 and " + std::to_string(kMaxBins) + ", got " +
                    std::to_string(options.bins));
    if (!(options.traversal_cost >= 0.0f) || !(options.intersection_cost > 0.0f))
        throw Error("BVH build: SAH costs must be finite, traversal >= 0 and intersection > 0");
    if (primitive_bounds.size() > std::numeric_limits<uint32_t>::max())
        throw Error("BVH build: more than 2^32 - 1 primitives");
    // The escape layout packs the first primitive of a leaf into 24 bits.
    if (options.layout == BvhLayout::Escape && primitive_bounds.size() > RT_ESCAPE_FIRST_MASK)
        throw Error("BVH build: the escape layout indexes at most " + std::to_string(RT_ESCAPE_FIRST_MASK) +
                    " primitives, got " + std::to_string(primitive_bounds.size()) + " (use the stack layout)");
}

}  // namespace

bool bvh_usable_bounds(const Aabb& box) {
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(box.lower[axis]) || !std::isfinite(box.upper[axis])) return false;
        if (box.lower[axis] > box.upper[axis]) return false;
    }
    return true;
}

BvhTree build_bvh_tree(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options,
                       const BvhProgress& progress) {
    check_options(primitive_bounds, options);
    BvhTree tree;
    TreeBuilder builder(primitive_bounds, options, tree, resolve_threads(options.threads), progress);
    builder.build();
    return tree;
}

Bvh build_bvh(std::span<const Aabb> primitive_bounds, const BvhBuildOptions& options, const BvhProgress& progress) {
    auto start = std::chrono::steady_clock::now();
    BvhTree tree = build_bvh_tree(primitive_bounds, options, progress);
    Bvh bvh;
    bvh.nodes = flatten_bvh_tree(tree, options.layout == BvhLayout::Wide ? BvhLayout::Stack : options.layout);
    if (options.layout == BvhLayout::Wide) bvh.wide_nodes = collapse_bvh_wide(bvh.nodes, options.wide_leaf_size);
    bvh.primitive_order = std::move(tree.primitive_order);
    bvh.layout = options.layout;
    bvh.options = options;
    bvh.options.threads = uint32_t(resolve_threads(options.threads));
    bvh.primitive_count = uint32_t(primitive_bounds.size());
    bvh.depth = tree.depth;
    bvh.sah_cost = sah_cost(bvh, options);
    bvh.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace prism

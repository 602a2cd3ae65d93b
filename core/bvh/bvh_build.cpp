// BVH builders into the intermediate tree: binned SAH and the seed's median split (thesis 6.2.1, Algorithm 6-1).
//
// Determinism: every split decision is taken by one thread from values that do not depend on how the work was
// divided. Parallel passes bin, bound or partition primitives in pieces, and their partial results merge with
// min/max and integer sums, which are exact and order-independent; a large node is partitioned in chunks of a fixed
// size, never one per thread, so the order it leaves its references in is the same too. So the tree is the same
// for any thread count, and images are bit-identical run to run.
#include <algorithm>
#include <bit>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>

#include "core/bvh/bvh.h"
#include "core/bvh/bvh_float4.h"
#include "core/bvh/bvh_tree.h"
#include "core/util/error.h"

namespace prism {

namespace {

constexpr uint32_t kTaskThreshold = 4096;              // subtrees larger than this may run on another thread
constexpr uint32_t kParallelPassThreshold = 1u << 16;  // binning/bounding passes this large are split in chunks
constexpr uint32_t kPassChunk = 1u << 15;
// Nodes this large are partitioned chunk by chunk (each chunk in place, then the references on the wrong side of
// the node's split point exchanged), which threads can share; smaller ones in one sweep.
constexpr uint32_t kChunkedPartitionFrom = kParallelPassThreshold;
constexpr uint32_t kPartitionChunk = 1u << 14;
// Below this depth every split is an index median, so no input can make the tree deeper than
// kBalancedDepth + log2(primitives): with 2^24 primitives that still fits RT_BVH_STACK_SIZE (64). Real meshes never
// get near it (the bunny's SAH tree is ~25 deep).
constexpr uint32_t kBalancedDepth = 40;
constexpr uint32_t kMaxBins = 256;
constexpr uint32_t kFewestBins = 4;
constexpr uint32_t kTwoBinSetsFrom = 1024;  // primitives
constexpr uint32_t kPrimitivesPerExtraBin = 20;

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
    // Takes threads back whether or not any are spare: the count may go below zero for a while, and no thread
    // starts until it is positive again.
    void take_back(int count) { spare_ -= count; }

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

using bvh_simd::Box4;
using bvh_simd::Float4;
using bvh_simd::Lanes;

// One primitive in the working array. Builders move these (not indices into the caller's bounds) so every pass
// reads memory in order; 32 bytes, two aligned SSE loads.
struct alignas(16) Reference {
    float lower[4];  // lower[3]: the primitive index's bits
    float upper[4];  // upper[3]: 0
    Float4 lo() const { return bvh_simd::load(lower); }
    Float4 hi() const { return bvh_simd::load(upper); }
    // Twice the centroid, computed the same way everywhere, so bins and partitions see identical values.
    Float4 centroid2() const { return bvh_simd::xyz(lo()) + hi(); }
    uint32_t primitive() const { return std::bit_cast<uint32_t>(lower[3]); }
};

struct RangeBounds {
    Box4 box;        // of the primitive bounds
    Box4 centroids;  // of the primitives' doubled centroids (Reference::centroid2)
    void grow(const Reference& reference) {
        box.grow(reference.lo(), reference.hi());
        centroids.grow(reference.centroid2());
    }
    void grow(const RangeBounds& other) {
        box.grow(other.box);
        centroids.grow(other.centroids);
    }
};

Aabb to_aabb(const Box4& box) {
    Lanes lower = bvh_simd::lanes(box.lower), upper = bvh_simd::lanes(box.upper);
    Aabb out;
    out.lower = {lower.v[0], lower.v[1], lower.v[2]};
    out.upper = {upper.v[0], upper.v[1], upper.v[2]};
    return out;
}

// Maps doubled centroids to bins on all three axes at once; the same function counts and partitions, so both agree.
struct Binning {
    Float4 origin = bvh_simd::splat(0.0f);
    Float4 scale = bvh_simd::splat(0.0f);  // 0 on an axis that cannot be binned (no centroid extent)
    Float4 last_bin = bvh_simd::splat(0.0f);
    uint32_t count = 0;  // bins per axis
    bool usable[3] = {false, false, false};
    void bins_of(const Reference& reference, int32_t (&bins)[4]) const {
        Float4 position = (reference.centroid2() - origin) * scale;
        bvh_simd::truncate(bvh_simd::min(bvh_simd::max(position, bvh_simd::splat(0.0f)), last_bin), bins);
    }
};

// Bin boxes and counts per axis: entry axis * bins + bin.
struct BinSet {
    std::vector<Box4> boxes;
    std::vector<uint32_t> counts;
    void reset(uint32_t bins) {
        boxes.assign(3 * bins, Box4{});
        counts.assign(3 * bins, 0);
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
        : options_(options), tree_(tree), threads_(threads), budget_(threads - 1), progress_(progress) {
        max_leaf_ = options.max_leaf_size;
        if (options.layout == BvhLayout::Escape) max_leaf_ = std::min<uint32_t>(max_leaf_, 255u);
        // The wide layout packs a leaf's count in 3 bits and tests its primitives four at a time: its SAH counts
        // blocks of four (as Embree does).
        if (options.layout == BvhLayout::Wide) max_leaf_ = std::min<uint32_t>(max_leaf_, RT_WIDE_LEAF_MAX);
        leaf_block_ = options.layout == BvhLayout::Wide ? 4u : 1u;
        make_references(bounds);
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
        uint32_t depth = 0;
        tree_.root = build_subtree(root, arena, depth);
        tree_.node_count = 0;
        for (const auto& nodes : tree_.arenas) tree_.node_count += uint32_t(nodes.size());
        tree_.depth = depth;
        tree_.primitive_order.resize(count);
        int helpers = helpers_for(count);
        run_in_parts(0, count, helpers + 1, [&](uint32_t b, uint32_t e, int) {
            for (uint32_t i = b; i < e; ++i) tree_.primitive_order[i] = references_[i].primitive();
        });
        budget_.release(helpers);
    }

private:
    std::deque<BvhBuildNode>& new_arena() {
        std::lock_guard lock(arenas_mutex_);
        return tree_.arenas.emplace_back();
    }

    // The usable bounds in input order, made in chunks on all threads: counted first, so each chunk knows where its
    // references go (and the memory they fill is first touched by as many threads).
    void make_references(std::span<const Aabb> bounds) {
        uint32_t size = uint32_t(bounds.size());
        int helpers = helpers_for(size);
        std::vector<uint32_t> usable(helpers + 1), first(helpers + 1);
        run_in_parts(0, size, helpers + 1, [&](uint32_t b, uint32_t e, int part) {
            for (uint32_t i = b; i < e; ++i) usable[part] += bvh_usable_bounds(bounds[i]) ? 1 : 0;
        });
        uint32_t total = 0;
        for (int part = 0; part <= helpers; ++part) first[part] = total, total += usable[part];
        references_.resize(total);  // left uninitialized (UninitializedAllocator): the chunks fill every one
        run_in_parts(0, size, helpers + 1, [&](uint32_t b, uint32_t e, int part) {
            Reference* out = references_.data() + first[part];
            for (uint32_t i = b; i < e; ++i) {
                const Aabb& box = bounds[i];
                if (!bvh_usable_bounds(box)) continue;
                *out++ = Reference{{box.lower.x, box.lower.y, box.lower.z, std::bit_cast<float>(i)},
                                   {box.upper.x, box.upper.y, box.upper.z, 0.0f}};
            }
        });
        budget_.release(helpers);
    }

    // A pass takes at most its node's share of the threads (by references): the two halves of a node split at the
    // same time, and the first to ask would otherwise take every spare thread, leaving the other's passes serial.
    // (The passes over the whole input, before references_ is filled, are not held back.)
    int helpers_for(uint32_t count) {
        if (count < kParallelPassThreshold) return 0;
        int share = std::max(1, int(uint64_t(threads_) * count / std::max<size_t>(1, references_.size())));
        return budget_.acquire(std::min(int(count / kPassChunk), share) - 1);
    }

    RangeBounds bounds_of(uint32_t begin, uint32_t end) {
        int helpers = helpers_for(end - begin);
        std::vector<RangeBounds> parts(helpers + 1);
        run_in_parts(begin, end, helpers + 1, [&](uint32_t b, uint32_t e, int part) {
            RangeBounds bounds;
            for (uint32_t i = b; i < e; ++i) bounds.grow(references_[i]);
            parts[part] = bounds;
        });
        budget_.release(helpers);
        RangeBounds total;
        for (const auto& part : parts) total.grow(part);
        return total;
    }

    // `deepest` is the calling thread's own (shared counters would bounce between cores once per node).
    const BvhBuildNode* build_subtree(const Task& task, std::deque<BvhBuildNode>& arena, uint32_t& deepest) {
        BvhBuildNode& node = arena.emplace_back();
        node.box = to_aabb(task.bounds.box);
        deepest = std::max(deepest, task.depth + 1);

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
            uint32_t worker_deepest = 0;
            std::thread worker([&] {
                node.children[0] = build_subtree(left, new_arena(), worker_deepest);
                budget_.release(1);
            });
            node.children[1] = build_subtree(right, arena, deepest);
            // Waiting for the worker, this thread is idle: its core may start other work meanwhile.
            budget_.release(1);
            worker.join();
            budget_.take_back(1);
            deepest = std::max(deepest, worker_deepest);
        } else {
            node.children[0] = build_subtree(left, arena, deepest);
            node.children[1] = build_subtree(right, arena, deepest);
        }
        node.nodes = 1 + node.children[0]->nodes + node.children[1]->nodes;
        return &node;
    }

    float blocks(uint32_t count) const { return float((count + leaf_block_ - 1) / leaf_block_); }

    // Decides leaf or split; on a split, partitions the references and fills both child tasks.
    bool split(const Task& task, Task& left, Task& right) {
        uint32_t count = task.end - task.begin;
        if (count <= 1) return false;
        if (task.depth >= kBalancedDepth) return count > max_leaf_ && split_at_index_median(task, left, right);
        if (options_.method == BvhMethod::Median) return count > max_leaf_ && split_at_box_median(task, left, right);

        Split best = find_binned_split(task);
        if (count <= max_leaf_) {
            // Small enough for a leaf: split only where the SAH says it pays.
            if (best.axis < 0) return false;
            float area = task.bounds.box.half_area();
            float leaf_cost = options_.intersection_cost * area * blocks(count);
            float split_cost = options_.traversal_cost * area + options_.intersection_cost * best.cost;
            if (leaf_cost <= split_cost) return false;
        }
        if (best.axis < 0) return split_at_index_median(task, left, right);  // all centroids equal

        Binning binning = binning_for(task.bounds.centroids, count);
        int axis = best.axis;
        return partition(task, left, right, [&](const Reference& reference) {
            int32_t bins[4];
            binning.bins_of(reference, bins);
            return uint32_t(bins[axis]) <= best.last_left_bin;
        });
    }

    // Moves the references that satisfy goes_left to the front, measuring both sides on the way.
    template <class Predicate>
    bool partition(const Task& task, Task& left, Task& right, const Predicate& goes_left) {
        RangeBounds left_bounds, right_bounds;
        uint32_t middle = task.end - task.begin >= kChunkedPartitionFrom
                              ? partition_in_chunks(task.begin, task.end, goes_left, left_bounds, right_bounds)
                              : partition_range(task.begin, task.end, goes_left, left_bounds, right_bounds);
        if (middle == task.begin || middle == task.end) return split_at_index_median(task, left, right);
        left = {task.begin, middle, left_bounds, task.depth + 1};
        right = {middle, task.end, right_bounds, task.depth + 1};
        return true;
    }

    // One two-sided sweep over [begin, end); returns where the right side starts.
    template <class Predicate>
    uint32_t partition_range(uint32_t begin, uint32_t end, const Predicate& goes_left, RangeBounds& left_bounds,
                             RangeBounds& right_bounds) {
        uint32_t i = begin, j = end;
        for (;;) {
            while (i < j && goes_left(references_[i])) left_bounds.grow(references_[i++]);
            while (i < j && !goes_left(references_[j - 1])) right_bounds.grow(references_[--j]);
            if (i == j) return i;
            // references_[i] goes right and references_[j - 1] left: exchange them.
            std::swap(references_[i], references_[j - 1]);
            left_bounds.grow(references_[i++]);
            right_bounds.grow(references_[--j]);
        }
    }

    // Each kPartitionChunk-sized chunk is partitioned in place on its own (in parallel when threads are spare);
    // then the right-goers still before the node's split point and the left-goers after it, equally many, are
    // exchanged in position order. Both steps' results depend on the chunk size only.
    template <class Predicate>
    uint32_t partition_in_chunks(uint32_t begin, uint32_t end, const Predicate& goes_left, RangeBounds& left_bounds,
                                 RangeBounds& right_bounds) {
        const uint32_t chunks = (end - begin + kPartitionChunk - 1) / kPartitionChunk;
        auto chunk_begin = [&](uint32_t c) { return begin + c * kPartitionChunk; };
        auto chunk_end = [&](uint32_t c) { return std::min(end, begin + (c + 1) * kPartitionChunk); };
        struct Chunk {
            uint32_t middle;
            RangeBounds left, right;
        };
        std::vector<Chunk> parts(chunks);
        int helpers = helpers_for(end - begin);
        run_in_parts(0, chunks, std::min<int>(helpers + 1, int(chunks)), [&](uint32_t first, uint32_t last, int) {
            for (uint32_t c = first; c < last; ++c)
                parts[c].middle =
                    partition_range(chunk_begin(c), chunk_end(c), goes_left, parts[c].left, parts[c].right);
        });
        uint32_t middle = begin;
        for (const Chunk& part : parts) {
            left_bounds.grow(part.left);
            right_bounds.grow(part.right);
            middle += part.middle - chunk_begin(uint32_t(&part - parts.data()));
        }

        // Misplaced runs: right-goers in [begin, middle) and left-goers in [middle, end), each in position order.
        struct Run {
            uint32_t first, last;
        };
        std::vector<Run> wrong_right, wrong_left;
        for (uint32_t c = 0; c < chunks; ++c) {
            Run right_goers{std::max(parts[c].middle, begin), std::min(chunk_end(c), middle)};
            if (right_goers.first < right_goers.last) wrong_right.push_back(right_goers);
            Run left_goers{std::max(chunk_begin(c), middle), std::min(parts[c].middle, end)};
            if (left_goers.first < left_goers.last) wrong_left.push_back(left_goers);
        }
        // Pair them up into exchanges of equal length.
        struct Exchange {
            uint32_t a, b, length;
        };
        std::vector<Exchange> exchanges;
        for (size_t r = 0, l = 0; r < wrong_right.size() && l < wrong_left.size();) {
            Run& a = wrong_right[r];
            Run& b = wrong_left[l];
            uint32_t length = std::min(a.last - a.first, b.last - b.first);
            exchanges.push_back({a.first, b.first, length});
            a.first += length, b.first += length;
            if (a.first == a.last) ++r;
            if (b.first == b.last) ++l;
        }
        run_in_parts(0, uint32_t(exchanges.size()), std::max(1, std::min<int>(helpers + 1, int(exchanges.size()))),
                     [&](uint32_t first, uint32_t last, int) {
                         for (uint32_t e = first; e < last; ++e)
                             std::swap_ranges(references_.begin() + exchanges[e].a,
                                              references_.begin() + exchanges[e].a + exchanges[e].length,
                                              references_.begin() + exchanges[e].b);
                     });
        budget_.release(helpers);
        return middle;
    }

    // Fewer bins for fewer primitives (most of a small node's bins would stay empty, yet each costs a reset and a
    // step of the cost sweep), the option for large ones (the same rule as Embree's binning).
    uint32_t bins_for(uint32_t primitives) const {
        return std::min(options_.bins, kFewestBins + primitives / kPrimitivesPerExtraBin);
    }

    Binning binning_for(const Box4& centroids, uint32_t primitives) const {
        Binning binning;
        binning.count = bins_for(primitives);
        Lanes lower = bvh_simd::lanes(centroids.lower), upper = bvh_simd::lanes(centroids.upper);
        float scale[3];
        for (int axis = 0; axis < 3; ++axis) {
            float extent = upper.v[axis] - lower.v[axis];
            scale[axis] = extent > 0.0f ? float(binning.count) / extent : 0.0f;
            if (!std::isfinite(scale[axis])) scale[axis] = 0.0f;
            binning.usable[axis] = scale[axis] != 0.0f;
        }
        binning.origin = bvh_simd::set(lower.v[0], lower.v[1], lower.v[2], 0.0f);
        binning.scale = bvh_simd::set(scale[0], scale[1], scale[2], 0.0f);
        binning.last_bin = bvh_simd::splat(float(binning.count - 1));
        return binning;
    }

    static void bin_one(const Reference& reference, const Binning& binning, BinSet& set) {
        int32_t bins[4];
        binning.bins_of(reference, bins);
        Float4 lower = reference.lo(), upper = reference.hi();
        for (uint32_t axis = 0; axis < 3; ++axis) {
            uint32_t slot = axis * binning.count + uint32_t(bins[axis]);
            set.boxes[slot].grow(lower, upper);
            set.counts[slot]++;
        }
    }

    // Adds references [begin, end) to `set` (reset). Long ranges alternate between it and `spare`: neighbouring
    // references often fall in the same bins, and with one set each update would wait for the previous one's store.
    void bin_range(uint32_t begin, uint32_t end, const Binning& binning, BinSet& set, BinSet& spare) const {
        if (end - begin < kTwoBinSetsFrom) {
            for (uint32_t i = begin; i < end; ++i) bin_one(references_[i], binning, set);
            return;
        }
        spare.reset(binning.count);
        uint32_t i = begin;
        for (; i + 1 < end; i += 2) {
            bin_one(references_[i], binning, set);
            bin_one(references_[i + 1], binning, spare);
        }
        if (i < end) bin_one(references_[i], binning, set);
        for (uint32_t slot = 0; slot < 3 * binning.count; ++slot) {
            set.boxes[slot].grow(spare.boxes[slot]);
            set.counts[slot] += spare.counts[slot];
        }
    }

    Split find_binned_split(const Task& task) {
        Binning binning = binning_for(task.bounds.centroids, task.end - task.begin);
        const uint32_t bin_count = binning.count;

        // Reused per thread: a node's binning finishes before its children start.
        thread_local BinSet bins, spare;
        bins.reset(bin_count);
        int helpers = helpers_for(task.end - task.begin);
        if (helpers == 0) {
            bin_range(task.begin, task.end, binning, bins, spare);
        } else {
            std::vector<BinSet> parts(helpers + 1), spares(helpers + 1);
            run_in_parts(task.begin, task.end, helpers + 1, [&](uint32_t b, uint32_t e, int part) {
                parts[part].reset(bin_count);
                bin_range(b, e, binning, parts[part], spares[part]);
            });
            budget_.release(helpers);
            for (const auto& part : parts)
                for (uint32_t i = 0; i < 3 * bin_count; ++i) {
                    bins.boxes[i].grow(part.boxes[i]);
                    bins.counts[i] += part.counts[i];
                }
        }

        Split best;
        float right_costs[kMaxBins];  // area * count of bins i.. on the right
        for (int axis = 0; axis < 3; ++axis) {
            if (!binning.usable[axis]) continue;
            const Box4* boxes = &bins.boxes[axis * bin_count];
            const uint32_t* counts = &bins.counts[axis * bin_count];
            // Empty bins are skipped: a split after one equals the split after the last non-empty bin before it,
            // which comes first and so wins the strict comparison anyway.
            Box4 sum;
            uint32_t sum_count = 0;
            float right_cost = 0.0f;
            for (uint32_t i = bin_count; i-- > 1;) {
                if (counts[i] != 0) {
                    sum.grow(boxes[i]);
                    sum_count += counts[i];
                    right_cost = sum.half_area() * blocks(sum_count);
                }
                right_costs[i] = sum_count ? right_cost : -1.0f;
            }
            Box4 left;
            uint32_t left_count = 0;
            for (uint32_t i = 0; i + 1 < bin_count; ++i) {
                if (counts[i] == 0) continue;
                left.grow(boxes[i]);
                left_count += counts[i];
                if (right_costs[i + 1] < 0.0f) continue;
                float cost = left.half_area() * blocks(left_count) + right_costs[i + 1];
                if (cost < best.cost) best = {axis, i, cost};
            }
        }
        return best;
    }

    // Primitives in leaves so far, reported when a whole percent more of them is placed (whichever thread crosses it).
    void report_leaf(uint32_t count) {
        const uint64_t total = references_.size();
        uint64_t placed = placed_.fetch_add(count, std::memory_order_relaxed) + count;
        uint32_t percent = uint32_t(placed * 100 / total);
        uint32_t reported = reported_percent_.load(std::memory_order_relaxed);
        if (percent > reported && reported_percent_.compare_exchange_strong(reported, percent))
            progress_(double(placed) / double(total));
    }

    // Thesis Algorithm 6-1: pivot at the middle of the node box on an axis cycling x, y, z per level; primitives
    // go left when their centroid lies below it (compared doubled: exact, so the same split as undoubled). An empty
    // side falls back to the index median.
    bool split_at_box_median(const Task& task, Task& left, Task& right) {
        int axis = int(task.depth % 3);
        float pivot2 = bvh_simd::lanes(task.bounds.box.lower + task.bounds.box.upper).v[axis];
        return partition(task, left, right, [&](const Reference& reference) {
            return bvh_simd::lanes(reference.centroid2()).v[axis] < pivot2;
        });
    }

    bool split_at_index_median(const Task& task, Task& left, Task& right) {
        uint32_t mid = task.begin + (task.end - task.begin) / 2;
        left = {task.begin, mid, bounds_of(task.begin, mid), task.depth + 1};
        right = {mid, task.end, bounds_of(mid, task.end), task.depth + 1};
        return true;
    }

    const BvhBuildOptions& options_;
    BvhTree& tree_;
    int threads_;  // the build's, the calling thread's among them
    ThreadBudget budget_;
    uint32_t max_leaf_ = 4;
    UninitializedVector<Reference> references_;
    std::mutex arenas_mutex_;
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
    using Clock = std::chrono::steady_clock;
    auto start = Clock::now(), step = start;
    auto lap = [&step] {
        auto now = Clock::now();
        double ms = std::chrono::duration<double, std::milli>(now - step).count();
        step = now;
        return ms;
    };
    const uint32_t threads = uint32_t(resolve_threads(options.threads));
    BvhTree tree = build_bvh_tree(primitive_bounds, options, progress);
    Bvh bvh;
    bvh.phases.tree_ms = lap();
    bvh.nodes = flatten_bvh_tree(tree, options.layout == BvhLayout::Wide ? BvhLayout::Stack : options.layout, threads);
    bvh.phases.flatten_ms = lap();
    if (options.layout == BvhLayout::Wide) {
        bvh.wide_nodes = collapse_bvh_wide(bvh.nodes, options.wide_leaf_size, threads);
        bvh.phases.collapse_ms = lap();
    }
    bvh.primitive_order = std::move(tree.primitive_order);
    bvh.layout = options.layout;
    bvh.options = options;
    bvh.options.threads = threads;
    bvh.primitive_count = uint32_t(primitive_bounds.size());
    bvh.depth = tree.depth;
    lap();
    bvh.sah_cost = sah_cost(bvh, options);
    bvh.phases.sah_ms = lap();
    bvh.build_ms = std::chrono::duration<double, std::milli>(step - start).count();
    return bvh;
}

}  // namespace prism

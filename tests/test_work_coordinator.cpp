// The coordinator of a split render (apps/work_coordinator.h), driven with simulated workers of known speeds.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "apps/work_coordinator.h"

namespace {

using prism::app::MessageKind;
using prism::app::WorkCoordinator;
using prism::app::WorkerNaming;
using prism::app::WorkMessage;

struct Simulated {
    double ms_per_item;
    double busy_until = 0.0;  // virtual clock
    int32_t item = -1;
    bool done = false;
};

WorkMessage hello(int worker) {
    WorkMessage m;
    m.kind = MessageKind::Hello;
    m.worker = worker;
    m.text = "sim\nsimulated";
    return m;
}

// Runs every worker in virtual time: the one that finishes first returns its item and asks for the next.
// Returns the virtual time at which the last item came back; `rendered` collects every item returned.
double run(WorkCoordinator& coordinator, std::vector<Simulated>& workers, std::multiset<int32_t>& rendered) {
    for (size_t w = 0; w < workers.size(); ++w) {
        workers[w].item = coordinator.handle(0, hello(int(w)))->item;
        workers[w].busy_until = workers[w].item >= 0 ? workers[w].ms_per_item : 0.0;
        workers[w].done = workers[w].item < 0;
    }
    double last = 0.0;
    for (;;) {
        Simulated* next = nullptr;
        for (Simulated& s : workers)
            if (!s.done && (!next || s.busy_until < next->busy_until)) next = &s;
        if (!next) return last;
        WorkMessage result;
        result.kind = MessageKind::Result;
        result.worker = int32_t(next - workers.data());
        result.item = next->item;
        result.ms = next->ms_per_item;
        rendered.insert(next->item);
        last = std::max(last, next->busy_until);
        next->item = coordinator.handle(0, result)->item;
        if (next->item < 0)
            next->done = true;
        else
            next->busy_until += next->ms_per_item;
    }
}

TEST(WorkCoordinator, ASlowWorkerIsSentHomeRatherThanHoldUpTheEnd) {
    // A GPU at 1 ms an item beside a CPU at 12 ms: handing out in order alone, the CPU would take an item in the
    // last 12 ms and the frame would end up to 11 ms late.
    WorkCoordinator coordinator(100, {}, 0, 0, false, WorkerNaming::Device);
    std::vector<Simulated> workers{{1.0}, {12.0}};
    std::multiset<int32_t> rendered;
    const double end = run(coordinator, workers, rendered);
    EXPECT_EQ(rendered.size(), 100u);
    for (int32_t i = 0; i < 100; ++i) EXPECT_EQ(rendered.count(i), 1u) << i;
    // Together they render 100 items at 1/1 + 1/12 items a ms: about 92.3 ms; a ms of slack for the granularity.
    EXPECT_LE(end, 100.0 / (1.0 + 1.0 / 12.0) + 1.0);
    EXPECT_LE(workers[1].busy_until, end);
    coordinator.check_complete();
}

TEST(WorkCoordinator, AWorkerAloneIsNeverSentHome) {
    WorkCoordinator coordinator(7, {}, 0, 0, false, WorkerNaming::None);
    std::vector<Simulated> workers{{50.0}};
    std::multiset<int32_t> rendered;
    EXPECT_DOUBLE_EQ(run(coordinator, workers, rendered), 350.0);
    EXPECT_EQ(rendered.size(), 7u);
    coordinator.check_complete();
}

TEST(WorkCoordinator, EqualWorkersShareTheItems) {
    WorkCoordinator coordinator(40, {}, 0, 0, false, WorkerNaming::Device);
    std::vector<Simulated> workers{{2.0}, {2.0}, {2.0}, {2.0}};
    std::multiset<int32_t> rendered;
    EXPECT_DOUBLE_EQ(run(coordinator, workers, rendered), 20.0);
    EXPECT_EQ(rendered.size(), 40u);
    for (const prism::app::WorkerRecord& r : coordinator.workers()) EXPECT_EQ(r.items, 10u);
}

}  // namespace

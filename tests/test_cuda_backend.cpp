// What is particular to the `cuda` backend: without a CUDA device (this development machine, CI), asking for one is
// a clean prism::Error, not a crash; with one, devices are chosen by index or name. The contract every backend
// keeps (memory, limits, stages, determinism, images and ray queries against cpu-ref) is in
// test_backend_contract.cpp.
#ifdef PRISM_HAVE_CUDA

#include <cmath>
#include <cstdlib>
#include <optional>
#include <random>

#include <gtest/gtest.h>

#include "backends/backend_list.h"
#include "backends/cuda/cuda_backend.h"
#include "core/util/error.h"
#include "core/render/render_engine.h"
#include "core/loaders/scene_loader.h"
#include "tests/test_support.h"

namespace {

#define REQUIRE_CUDA_DEVICE()                                                           \
    do {                                                                                \
        std::string reason_;                                                            \
        /* probe()'s detail reads "no CUDA device (cudaGetDeviceCount: ...)" */         \
        if (!prism::test::backend_available("cuda", &reason_)) GTEST_SKIP() << reason_; \
    } while (0)

}  // namespace

// ---- Runs everywhere --------------------------------------------------------------------------------------------
TEST(CudaBackend, WithoutDeviceCreationIsACleanError) {
    std::string reason;
    if (prism::test::backend_available("cuda", &reason)) GTEST_SKIP() << "a CUDA device is present: " << reason;
    EXPECT_NE(reason.find("CUDA"), std::string::npos) << reason;
    EXPECT_NE(reason.find("no CUDA device"), std::string::npos) << reason;
    for (const char* name : {"cuda", "cuda:0", "cuda:h100"}) {
        try {
            prism::create_backend(name);
            ADD_FAILURE() << name << " created without a device";
        } catch (const prism::Error& error) {
            std::string message = error.what();
            EXPECT_NE(message.find("CUDA"), std::string::npos) << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
        }
    }
}

TEST(CudaBackend, ProbeReportsAvailabilityWithAReason) {
    prism::register_builtin_backends();
    const prism::BackendFactory* cuda = nullptr;
    for (const prism::BackendFactory& factory : prism::registered_backends())
        if (factory.name == "cuda") cuda = &factory;
    ASSERT_NE(cuda, nullptr) << "this build has CUDA enabled but did not register the backend";
    prism::BackendAvailability a = cuda->probe();
    EXPECT_EQ(a.name, "cuda");
    EXPECT_FALSE(a.detail.empty());
    EXPECT_EQ(a.available, !a.devices.empty());
}

// ---- Needs a CUDA device ----------------------------------------------------------------------------------------

TEST(CudaBackend, DeviceSelection) {
    REQUIRE_CUDA_DEVICE();
    EXPECT_NO_THROW(prism::create_backend("cuda:0"));
    std::string name = prism::create_backend("cuda")->info().device;
    EXPECT_NO_THROW(prism::create_backend("cuda:" + name.substr(0, name.find(' '))));  // e.g. "cuda:NVIDIA"
    try {
        prism::create_backend("cuda:no-such-gpu");
        ADD_FAILURE() << "an unknown device name was accepted";
    } catch (const prism::Error& error) {
        EXPECT_NE(std::string(error.what()).find("no device matches 'no-such-gpu'"), std::string::npos) << error.what();
    }
    EXPECT_THROW(prism::create_backend("cuda:99"), prism::Error);
}

#endif  // PRISM_HAVE_CUDA

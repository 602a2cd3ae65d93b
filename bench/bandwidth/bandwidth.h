// `prism bandwidth`: host<->device and device<->device copy bandwidth on every available CUDA, OpenCL and Vulkan
// device (the seed thesis's Figure 8-1, redone). apps/cmd_bandwidth.cpp parses the command line into Options.
#pragma once

#include <string>
#include <vector>

namespace prism::bandwidth {

struct Options {
    std::string sizes;  // "" = 4K..1G in powers of 4; else e.g. "1M" or "4K,16M,256M"
    int warmup = 2;
    int repeats = 10;
    std::vector<std::string> apis;     // subset of cuda, opencl, vulkan; empty = all
    std::vector<std::string> devices;  // filters "api:substring" or "substring"
    std::string json_path;             // "" = no JSON
    std::string plot_path;             // "" = no plot
};

// Measures, prints the tables, writes the files. Throws prism::Error for bad options or unwritable files;
// missing APIs and devices are reported in the output, not thrown.
void run_bandwidth(const Options& options);

}  // namespace prism::bandwidth

// The PCIe link of a device, read from Linux sysfs for the PCI address the API reports: the figure behind
// "% of link" for host<->device copies. Absent (not an error) where sysfs or the address is missing.
#pragma once

#include <optional>
#include <string>

#include "bench/bandwidth/measurement.h"

namespace prism::bandwidth {

// "dddd:bb:dd.f" from numeric parts.
std::string pci_address(unsigned domain, unsigned bus, unsigned device, unsigned function);
// Current link speed x width, per direction, after 8b/10b (<= 5 GT/s) or 128b/130b (>= 8 GT/s) encoding.
std::optional<LinkInfo> read_pci_link(const std::string& address);
// The same from sysfs-style text ("16.0 GT/s PCIe", "16"); exposed for tests.
std::optional<LinkInfo> link_from_sysfs_text(const std::string& speed, const std::string& width);

}  // namespace prism::bandwidth

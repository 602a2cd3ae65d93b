#include "bench/bandwidth/pci_link.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace prism::bandwidth {

std::string pci_address(unsigned domain, unsigned bus, unsigned device, unsigned function) {
    char text[32];
    std::snprintf(text, sizeof text, "%04x:%02x:%02x.%x", domain, bus, device, function);
    return text;
}

std::optional<LinkInfo> link_from_sysfs_text(const std::string& speed, const std::string& width) {
    double transfers = std::strtod(speed.c_str(), nullptr);  // GT/s per lane
    int lanes = std::atoi(width.c_str());
    if (transfers <= 0 || lanes <= 0) return std::nullopt;
    double encoding = transfers <= 5.0 ? 8.0 / 10.0 : 128.0 / 130.0;
    char description[64];
    std::snprintf(description, sizeof description, "PCIe %.1f GT/s x%d", transfers, lanes);
    return LinkInfo{description, transfers * lanes * encoding / 8.0};
}

std::optional<LinkInfo> read_pci_link(const std::string& address) {
    std::string dir = "/sys/bus/pci/devices/" + address + "/";
    std::string speed, width;
    std::ifstream speed_file(dir + "current_link_speed"), width_file(dir + "current_link_width");
    if (!std::getline(speed_file, speed) || !std::getline(width_file, width)) return std::nullopt;
    return link_from_sysfs_text(speed, width);
}

}  // namespace prism::bandwidth

// devices.cpp — `clhair devices`: every OpenCL device with its capabilities, and the
// sub-group backend clhair would use on each (opened, self-tested) or why it cannot.
#include <iostream>

#include "clhair/error.h"
#include "clhair/renderer.h"
#include "commands.h"
#include "options.h"

namespace clhair::cli {

namespace {

std::string mib(std::uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; }

}  // namespace

CLI::App* addDevicesCommand(CLI::App& app) {
  return app.add_subcommand("devices", "list OpenCL devices and their capabilities");
}

int cmdDevices(const DeviceOptions& opts) {
  std::vector<DeviceInfo> all = Device::list();
  if (all.empty())
    throw Error("no OpenCL devices found (install an OpenCL driver, e.g. pocl-opencl-icd)");
  for (const DeviceInfo& d : all) {
    std::cout << d.platformIndex << ":" << d.deviceIndex << "  " << d.name << "\n"
              << "    platform        " << d.platformName << "\n"
              << "    vendor          " << d.vendor << "\n"
              << "    OpenCL          " << d.version << " / " << d.clcVersion << "\n"
              << "    driver          " << d.driverVersion << "\n"
              << "    type            " << (d.isGpu ? "GPU" : "not GPU") << ", " << d.computeUnits
              << " compute units\n"
              << "    64-bit atomics  "
              << (d.int64Atomics ? "yes" : "no (clhair cannot use this device)") << "\n"
              << "    max allocation  " << mib(d.maxAlloc) << " of " << mib(d.globalMem) << "\n";
    std::string backend = "-";
    if (d.int64Atomics) {
      try {
        DeviceOptions o = opts;
        o.selector = std::to_string(d.platformIndex) + ":" + std::to_string(d.deviceIndex);
        Device dev = Device::open(o);
        backend = std::string(subgroupBackendName(dev.info().backend)) + " (" +
                  dev.info().backendNote + ")";
      } catch (const Error& e) {
        std::string msg = e.what();
        backend = "unavailable: " + msg.substr(0, msg.find('\n'));
      }
    }
    std::string cands;
    for (SubgroupBackend b : d.candidates)
      cands += std::string(cands.empty() ? "" : ", ") + subgroupBackendName(b);
    std::cout << "    sub-group       " << backend << "; candidates: " << cands << "\n";
  }
  return 0;
}

}  // namespace clhair::cli

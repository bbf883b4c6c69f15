// `simpli devices`: lists the OpenCL devices and, with --check, runs the engine self-check on
// the selected one.
#include "commands.h"

#include <CLI/CLI.hpp>
#include "simpli/error.h"
#include "simpli/ocl/device.h"
#include "simpli/ocl/self_check.h"

#include <iostream>

namespace simpli::app {

void addDevicesCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("devices", "List OpenCL devices; --check runs a self-check");
  auto check = std::make_shared<bool>(false);
  auto selector = std::make_shared<std::string>();
  cmd->add_flag("--check", *check, "Run the engine self-check on the selected device");
  cmd->add_option("--device", *selector,
                  "Device as platform:device (default: $SIMPLI_CL_DEVICE, else first GPU, "
                  "else first CPU)");
  cmd->callback([check, selector] {
    const auto devices = ocl::listDevices();
    if (!selector->empty()) {
      auto [p, d] = ocl::Device::parseSelector(*selector, "--device");
      ocl::Device::select(p, d);
    }
    const auto& current = ocl::Device::current().info();
    std::cout << "OpenCL devices (select with --device p:d or SIMPLI_CL_DEVICE=p:d):\n";
    for (const auto& info : devices) {
      const bool isCurrent =
          info.platformIndex == current.platformIndex && info.deviceIndex == current.deviceIndex;
      std::cout << (isCurrent ? "* " : "  ") << info.platformIndex << ':' << info.deviceIndex
                << "  " << (info.isGpu ? "GPU" : "CPU") << "  " << info.deviceName << "  ["
                << info.platformName << ", " << info.deviceVersion << ", driver "
                << info.driverVersion << "]  " << info.computeUnits << " CU, "
                << (info.globalMemBytes >> 20) << " MiB, fp64 " << (info.hasFp64 ? "yes" : "no")
                << '\n';
    }
    if (*check && !ocl::runSelfCheck(std::cout))
      fail("self-check failed on device ", current.platformIndex, ':', current.deviceIndex, " (",
           current.deviceName, ")");
  });
}

} // namespace simpli::app

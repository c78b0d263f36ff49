// `smokesvd info`: every Vulkan device with the limits that matter, the chosen one marked.
#include <iostream>
#include <nlohmann/json.hpp>

#include "runtime/context.h"
#include "tools/smokesvd/command.h"

namespace smokesvd::cli {
namespace {

std::string version(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

nlohmann::json toJson(const DeviceInfo& d, bool chosen) {
  return {{"index", d.index}, {"name", d.name}, {"type", d.typeName()}, {"chosen", chosen},
          {"api_version", version(d.apiVersion)}, {"driver", d.driver},
          {"max_storage_buffer_range", d.maxStorageBufferRange}, {"max_texel_buffer_elements", d.maxTexelBufferElements},
          {"max_tensor_bytes", d.maxTensorBytes()},
          {"max_shared_memory", d.maxSharedMemoryBytes}, {"max_workgroup_invocations", d.maxWorkgroupInvocations},
          {"subgroup_size", d.subgroupSize}, {"device_local_bytes", d.deviceLocalBytes},
          {"unified_memory", d.unifiedMemory}, {"float16", d.float16}, {"float32_atomic_add", d.float32AtomicAdd},
          {"push_descriptor", d.pushDescriptor}, {"timestamps", d.timestamps}};
}

void printDevice(const DeviceInfo& d, bool chosen) {
  auto mib = [](uint64_t bytes) { return std::to_string(bytes >> 20) + " MiB"; };
  auto yes = [](bool value) { return value ? "yes" : "no"; };
  std::cout << (chosen ? "* " : "  ") << d.index << ": " << d.name << " (" << d.typeName() << ", Vulkan "
            << version(d.apiVersion) << ", " << d.driver << ")\n"
            << "      largest tensor " << mib(d.maxTensorBytes()) << ", storage buffer range "
            << mib(d.maxStorageBufferRange) << ", texel buffer "
            << d.maxTexelBufferElements << " elements, shared memory " << d.maxSharedMemoryBytes / 1024
            << " KiB, workgroup " << d.maxWorkgroupInvocations << " invocations, subgroup " << d.subgroupSize << "\n"
            << "      device-local memory " << mib(d.deviceLocalBytes) << (d.unifiedMemory ? " (unified)" : "")
            << ", fp16 " << yes(d.float16) << ", float32 atomic add " << yes(d.float32AtomicAdd)
            << ", push descriptors " << yes(d.pushDescriptor) << ", timestamps " << yes(d.timestamps) << "\n";
}

void addInfoCommand(CLI::App& app, const GlobalOptions& global, Action& action) {
  CLI::App* command = app.add_subcommand("info", "list Vulkan devices and their limits; * marks the one smokesvd uses");
  static bool json = false;
  command->add_flag("--json", json, "print JSON");
  command->callback([&global, &action] {
    action = [&global] {
      const std::vector<DeviceInfo> devices = Context::listDevices();
      const Context context(global.contextOptions());
      const uint32_t chosen = context.info().index;
      if (json) {
        nlohmann::json list = nlohmann::json::array();
        for (const DeviceInfo& d : devices) list.push_back(toJson(d, d.index == chosen));
        std::cout << nlohmann::json{{"devices", list}}.dump(2) << "\n";
        return;
      }
      for (const DeviceInfo& d : devices) printDevice(d, d.index == chosen);
    };
  });
}

const bool registered = registerCommand({"info", addInfoCommand});

}  // namespace
}  // namespace smokesvd::cli

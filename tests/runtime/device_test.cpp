#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>

#include "runtime/device_info.h"
#include "runtime/error.h"

namespace smokesvd::testing {
namespace {

std::vector<DeviceInfo> fakeDevices() {
  DeviceInfo cpu;
  cpu.index = 0;
  cpu.name = "llvmpipe (LLVM 15.0.6, 256 bits)";
  cpu.type = VK_PHYSICAL_DEVICE_TYPE_CPU;
  DeviceInfo integrated;
  integrated.index = 1;
  integrated.name = "Intel(R) UHD Graphics";
  integrated.type = VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU;
  DeviceInfo discrete;
  discrete.index = 2;
  discrete.name = "NVIDIA H100";
  discrete.type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  return {cpu, integrated, discrete};
}

TEST(DeviceChoice, PrefersDiscreteThenIntegratedThenCpu) {
  std::vector<DeviceInfo> devices = fakeDevices();
  EXPECT_EQ(chooseDevice(devices, "").name, "NVIDIA H100");
  devices.pop_back();
  EXPECT_EQ(chooseDevice(devices, "").name, "Intel(R) UHD Graphics");
  devices.pop_back();
  EXPECT_EQ(chooseDevice(devices, "").name, "llvmpipe (LLVM 15.0.6, 256 bits)");
}

TEST(DeviceChoice, ByIndexOrNameSubstring) {
  const std::vector<DeviceInfo> devices = fakeDevices();
  EXPECT_EQ(chooseDevice(devices, "0").index, 0u);
  EXPECT_EQ(chooseDevice(devices, "LLVMPIPE").index, 0u);
  EXPECT_EQ(chooseDevice(devices, "h100").index, 2u);
}

TEST(DeviceChoice, UnknownDeviceListsTheAvailableOnes) {
  try {
    chooseDevice(fakeDevices(), "radeon");
    FAIL() << "expected an Error";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("'radeon'"), std::string::npos) << message;
    EXPECT_NE(message.find("2 'NVIDIA H100'"), std::string::npos) << message;
  }
  EXPECT_THROW(chooseDevice(fakeDevices(), "7"), Error);
  EXPECT_THROW(chooseDevice({}, ""), Error);
}

TEST(DeviceThreads, LpNumThreadsWhereSetTheHardwareThreadsOtherwise) {
  const char* saved = std::getenv("LP_NUM_THREADS");
  const std::string previous = saved != nullptr ? saved : "";
  setenv("LP_NUM_THREADS", "3", 1);
  EXPECT_EQ(cpuDeviceThreads(), 3u);
  const uint32_t hardware = std::max(std::thread::hardware_concurrency(), 1u);
  for (const char* unusable : {"0", "-2", "many", "4x", ""}) {
    setenv("LP_NUM_THREADS", unusable, 1);
    EXPECT_EQ(cpuDeviceThreads(), hardware) << "LP_NUM_THREADS='" << unusable << "'";
  }
  unsetenv("LP_NUM_THREADS");
  EXPECT_EQ(cpuDeviceThreads(), hardware);
  if (saved != nullptr) setenv("LP_NUM_THREADS", previous.c_str(), 1);
}

}  // namespace
}  // namespace smokesvd::testing

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace smokesvd::testing

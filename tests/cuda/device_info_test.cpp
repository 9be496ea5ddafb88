// The device query runs everywhere: with no driver or no device it must explain, not crash.
#include "gpu/cuda/device_info.h"

#include <gtest/gtest.h>

#include <iostream>

namespace tessera::cuda {
namespace {

TEST(CudaDeviceQuery, NeverThrowsAndExplainsAnAbsentDevice) {
  CudaDeviceInfo info;
  ASSERT_NO_THROW(info = queryCudaDevice());
  std::cout << info.summary() << "\n";
  RecordProperty("cuda_device", info.summary());
  if (info.available) {
    EXPECT_TRUE(info.reason.empty());
    EXPECT_GE(info.deviceCount, 1);
  } else {
    EXPECT_FALSE(info.reason.empty());
    EXPECT_EQ(info.summary().rfind("no CUDA device: ", 0), 0u) << info.summary();
  }
  EXPECT_GT(info.runtimeVersion, 0);
}

TEST(CudaDeviceQuery, IndexPastTheLastDeviceIsReportedNotFatal) {
  CudaDeviceInfo info = queryCudaDevice(1 << 20);
  EXPECT_FALSE(info.available);
  EXPECT_FALSE(info.reason.empty());
  // And the runtime is left usable for the next query.
  EXPECT_EQ(queryCudaDevice().available, queryCudaDevice().available);
}

TEST(CudaDeviceQuery, UuidStringHasNvidiaSmiShape) {
  CudaDeviceInfo info;
  for (int b = 0; b < 16; ++b) info.uuid[b] = uint8_t(b * 17);
  EXPECT_EQ(info.uuidString(), "GPU-00112233-4455-6677-8899-aabbccddeeff");
}

}  // namespace
}  // namespace tessera::cuda

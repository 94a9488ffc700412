// The OpenCL devices of this machine, listed once per call as (platform, device) pairs.
#pragma once
#include <string>
#include <vector>

#include "backends/opencl/cl_runtime.h"

namespace moldtex::cl {

struct Device {
  uint32_t platform_index = 0, device_index = 0;
  cl_platform_id platform = nullptr;
  cl_device_id device = nullptr;
  std::string name, platform_name;
  bool is_gpu = false;
  uint64_t global_memory = 0, max_allocation = 0;
};

// All devices of all platforms. Throws moldtex::Error(MOLDTEX_ERROR_UNAVAILABLE) with the
// reason if there is no runtime or no platform.
std::vector<Device> list_devices();

}  // namespace moldtex::cl

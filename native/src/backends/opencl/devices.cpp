#include "backends/opencl/devices.h"

#include "common/error.h"

namespace moldtex::cl {

namespace {

std::string platform_string(const Runtime& r, cl_platform_id p, cl_platform_info what) {
  size_t size = 0;
  if (r.clGetPlatformInfo(p, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "";
  std::string s(size, '\0');
  r.clGetPlatformInfo(p, what, size, s.data(), nullptr);
  s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
  return s;
}

std::string device_string(const Runtime& r, cl_device_id d, cl_device_info what) {
  size_t size = 0;
  if (r.clGetDeviceInfo(d, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "";
  std::string s(size, '\0');
  r.clGetDeviceInfo(d, what, size, s.data(), nullptr);
  s.resize(s.find('\0') == std::string::npos ? s.size() : s.find('\0'));
  return s;
}

}  // namespace

std::vector<Device> list_devices() {
  const Runtime& r = runtime();
  if (!r.loaded) fail(MOLDTEX_ERROR_UNAVAILABLE, r.error);
  cl_uint platform_count = 0;
  cl_int err = r.clGetPlatformIDs(0, nullptr, &platform_count);
  if (err != CL_SUCCESS || platform_count == 0)
    fail(MOLDTEX_ERROR_UNAVAILABLE,
         "The OpenCL runtime found no platform (" + error_name(err) +
             "): install an OpenCL driver, e.g. Debian's pocl-opencl-icd for the CPU");
  std::vector<cl_platform_id> platforms(platform_count);
  r.clGetPlatformIDs(platform_count, platforms.data(), nullptr);
  std::vector<Device> devices;
  for (uint32_t p = 0; p < platform_count; ++p) {
    cl_uint count = 0;
    if (r.clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS) continue;
    std::vector<cl_device_id> ids(count);
    r.clGetDeviceIDs(platforms[p], CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr);
    for (uint32_t d = 0; d < count; ++d) {
      Device dev;
      dev.platform_index = p;
      dev.device_index = d;
      dev.platform = platforms[p];
      dev.device = ids[d];
      dev.name = device_string(r, ids[d], CL_DEVICE_NAME);
      dev.platform_name = platform_string(r, platforms[p], CL_PLATFORM_NAME);
      cl_device_type type = 0;
      r.clGetDeviceInfo(ids[d], CL_DEVICE_TYPE, sizeof(type), &type, nullptr);
      dev.is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
      cl_ulong mem = 0, alloc = 0;
      r.clGetDeviceInfo(ids[d], CL_DEVICE_GLOBAL_MEM_SIZE, sizeof(mem), &mem, nullptr);
      r.clGetDeviceInfo(ids[d], CL_DEVICE_MAX_MEM_ALLOC_SIZE, sizeof(alloc), &alloc, nullptr);
      dev.global_memory = mem;
      dev.max_allocation = alloc;
      devices.push_back(dev);
    }
  }
  if (devices.empty())
    fail(MOLDTEX_ERROR_UNAVAILABLE, "The OpenCL platforms on this machine have no devices");
  return devices;
}

}  // namespace moldtex::cl

#include "backends/opencl/cl_runtime.h"

#include <dlfcn.h>

#include <mutex>

namespace moldtex::cl {

namespace {

Runtime load() {
  Runtime r;
  void* lib = nullptr;
  for (const char* name : {"libOpenCL.so.1", "libOpenCL.so"})
    if ((lib = dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
  if (!lib) {
    r.error =
        "No OpenCL runtime was found (libOpenCL.so.1): install your GPU driver's OpenCL "
        "support, or on Debian the packages ocl-icd-libopencl1 and pocl-opencl-icd";
    return r;
  }
#define MTX_CL_RESOLVE(name)                                                       \
  r.name = reinterpret_cast<decltype(&::name)>(dlsym(lib, #name));                 \
  if (!r.name) {                                                                   \
    r.error = "The OpenCL runtime lacks " #name ": it is older than OpenCL 1.2";   \
    return r;                                                                      \
  }
  MTX_CL_FUNCTIONS(MTX_CL_RESOLVE)
#undef MTX_CL_RESOLVE
  r.loaded = true;  // the library stays open for the life of the process
  return r;
}

}  // namespace

const Runtime& runtime() {
  static std::once_flag once;
  static Runtime r;
  std::call_once(once, [] { r = load(); });
  return r;
}

std::string error_name(cl_int code) {
  const char* name = "an OpenCL error";
  switch (code) {
    case CL_DEVICE_NOT_FOUND: name = "CL_DEVICE_NOT_FOUND"; break;
    case CL_DEVICE_NOT_AVAILABLE: name = "CL_DEVICE_NOT_AVAILABLE"; break;
    case CL_COMPILER_NOT_AVAILABLE: name = "CL_COMPILER_NOT_AVAILABLE"; break;
    case CL_MEM_OBJECT_ALLOCATION_FAILURE: name = "CL_MEM_OBJECT_ALLOCATION_FAILURE"; break;
    case CL_OUT_OF_RESOURCES: name = "CL_OUT_OF_RESOURCES"; break;
    case CL_OUT_OF_HOST_MEMORY: name = "CL_OUT_OF_HOST_MEMORY"; break;
    case CL_BUILD_PROGRAM_FAILURE: name = "CL_BUILD_PROGRAM_FAILURE"; break;
    case CL_INVALID_VALUE: name = "CL_INVALID_VALUE"; break;
    case CL_INVALID_DEVICE: name = "CL_INVALID_DEVICE"; break;
    case CL_INVALID_KERNEL_ARGS: name = "CL_INVALID_KERNEL_ARGS"; break;
    case CL_INVALID_ARG_SIZE: name = "CL_INVALID_ARG_SIZE"; break;
    case CL_INVALID_WORK_GROUP_SIZE: name = "CL_INVALID_WORK_GROUP_SIZE"; break;
    case CL_INVALID_BUFFER_SIZE: name = "CL_INVALID_BUFFER_SIZE"; break;
    case -1001: name = "CL_PLATFORM_NOT_FOUND_KHR, no OpenCL driver is installed"; break;
    default: break;
  }
  return std::string(name) + " (" + std::to_string(code) + ")";
}

}  // namespace moldtex::cl

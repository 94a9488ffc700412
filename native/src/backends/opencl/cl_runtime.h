// The OpenCL runtime, opened at run time with dlopen so that libmoldtex loads (and the
// CPU backend works) on machines without any OpenCL installed. Every entry point is
// resolved once; a missing runtime or symbol becomes a message, never a crash.
#pragma once
#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <string>

namespace moldtex::cl {

struct Runtime {
#define MTX_CL_FUNCTIONS(X)                                                                      \
  X(clGetPlatformIDs) X(clGetPlatformInfo) X(clGetDeviceIDs) X(clGetDeviceInfo)                  \
  X(clCreateContext) X(clReleaseContext) X(clCreateCommandQueue) X(clReleaseCommandQueue)         \
  X(clCreateBuffer) X(clReleaseMemObject) X(clCreateProgramWithSource) X(clBuildProgram)          \
  X(clGetProgramBuildInfo) X(clReleaseProgram) X(clCreateKernel) X(clReleaseKernel)               \
  X(clSetKernelArg) X(clEnqueueNDRangeKernel) X(clEnqueueReadBuffer) X(clEnqueueWriteBuffer)      \
  X(clEnqueueFillBuffer) X(clFinish)
#define MTX_CL_DECLARE(name) decltype(&::name) name = nullptr;
  MTX_CL_FUNCTIONS(MTX_CL_DECLARE)
#undef MTX_CL_DECLARE
  bool loaded = false;
  std::string error;  // why the runtime is unusable, in words a user can act on
};

// The process-wide runtime (loaded on first use, thread-safe).
const Runtime& runtime();

// "CL_OUT_OF_RESOURCES (-5)" and the like.
std::string error_name(cl_int code);

}  // namespace moldtex::cl

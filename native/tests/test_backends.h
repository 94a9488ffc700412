// test_backends.h — run a test on the CPU and on the first OpenCL device.
//
// Tests parameterised on Backend get a config pinned to that backend. Without an OpenCL
// device the OpenCL instances skip, or fail when MOLDTEX_REQUIRE_OPENCL=1 (as in CI).
#ifndef MOLDTEX_TESTS_TEST_BACKENDS_H
#define MOLDTEX_TESTS_TEST_BACKENDS_H

#include <cstdlib>
#include <string>

#include "test_util.h"

namespace mtx {

enum class Backend { Cpu, OpenCl };

inline std::string BackendName(const ::testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::Cpu ? "Cpu" : "OpenCl";
}

// Switches `c` to `backend`; false (with *why) when OpenCL has no device.
inline bool PinBackend(Backend backend, moldtex_sim_config& c, std::string* why) {
  c.backend = MOLDTEX_BACKEND_CPU;
  if (backend == Backend::Cpu) return true;
  uint32_t count = 0;
  if (moldtex_opencl_device_count(&count) != MOLDTEX_OK || count == 0) {
    *why = "no OpenCL device: " + LastError();
    return false;
  }
  moldtex_opencl_device_info info;
  moldtex_opencl_device_info_init(&info);
  if (moldtex_opencl_get_device(0, &info) != MOLDTEX_OK) {
    *why = LastError();
    return false;
  }
  c.backend = MOLDTEX_BACKEND_OPENCL;
  c.opencl_platform = info.platform_index;
  c.opencl_device = info.device_index;
  return true;
}

inline bool OpenClRequiredByEnv() {
  const char* v = std::getenv("MOLDTEX_REQUIRE_OPENCL");
  return v && *v && std::string(v) != "0";
}

// In a TEST_P body: pins config `c` to GetParam() or skips / fails.
#define MTX_PIN_BACKEND(c)                                                              \
  do {                                                                                  \
    std::string why_;                                                                   \
    if (!::mtx::PinBackend(GetParam(), (c), &why_)) {                                   \
      if (::mtx::OpenClRequiredByEnv()) FAIL() << "MOLDTEX_REQUIRE_OPENCL is set: " << why_; \
      GTEST_SKIP() << why_;                                                             \
    }                                                                                   \
  } while (0)

#define MTX_BACKENDS(suite) \
  INSTANTIATE_TEST_SUITE_P(, suite, ::testing::Values(::mtx::Backend::Cpu, ::mtx::Backend::OpenCl), \
                           ::mtx::BackendName)

}  // namespace mtx

#endif  // MOLDTEX_TESTS_TEST_BACKENDS_H

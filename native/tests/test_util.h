// test_util.h — GoogleTest helpers shared by the Moldtex test files.
#ifndef MOLDTEX_TESTS_TEST_UTIL_H
#define MOLDTEX_TESTS_TEST_UTIL_H

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>

#include "mesh_fixtures.h"
#include "moldtex.h"

namespace mtx {

constexpr double kPi = 3.14159265358979323846;

// A surface point as the header defines it: triangle in range, barycentrics
// non-negative (float round-off allowed: 1e-6) and summing to 1 (1e-5).
inline ::testing::AssertionResult ValidPoint(const moldtex_surface_point& p,
                                             uint32_t triangle_count) {
  if (p.triangle >= triangle_count)
    return ::testing::AssertionFailure()
           << "triangle " << p.triangle << " >= triangle_count " << triangle_count;
  for (int k = 0; k < 3; ++k)
    if (!(p.bary[k] >= -1e-6f))
      return ::testing::AssertionFailure() << "bary[" << k << "] = " << p.bary[k];
  const double s = double(p.bary[0]) + p.bary[1] + p.bary[2];
  if (!(std::fabs(s - 1.0) <= 1e-5))
    return ::testing::AssertionFailure() << "bary sum = " << s;
  return ::testing::AssertionSuccess();
}

inline std::string Str(const Vec3& v) {
  std::ostringstream os;
  os.precision(9);
  os << "(" << v[0] << ", " << v[1] << ", " << v[2] << ")";
  return os.str();
}

inline std::string LastError() { return std::string(moldtex_last_error()); }

// A fresh folder per test (named after the process and the running test), removed with
// everything in it when the object goes.
struct TempDir {
  std::filesystem::path path;
  TempDir() {
    static int counter = 0;
    path = std::filesystem::temp_directory_path() /
           ("moldtex_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() { std::filesystem::remove_all(path); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

}  // namespace mtx

#endif  // MOLDTEX_TESTS_TEST_UTIL_H

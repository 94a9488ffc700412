// bake_util.h — bake and checkpoint helpers shared by the Moldtex tests (bakes into a
// TempDir, whole-file reads).
#ifndef MOLDTEX_TESTS_BAKE_UTIL_H
#define MOLDTEX_TESTS_BAKE_UTIL_H

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "test_util.h"

namespace mtx {

// A bake of frames first..last into dir. The desc points at a copy of the folder name
// that lives until the next call.
inline moldtex_bake_desc BakeDesc(const TempDir& dir, int first, int last, uint32_t spf,
                                  uint32_t format = MOLDTEX_IMAGE_EXR_HALF) {
  moldtex_bake_desc d;
  moldtex_bake_desc_init(&d);
  static std::string directory;
  directory = dir.path.string();
  d.directory = directory.c_str();
  d.first_frame = first;
  d.last_frame = last;
  d.steps_per_frame = spf;
  d.format = format;
  return d;
}

// Starts the bake and waits for it; the worker's message in *message when given.
inline moldtex_status RunBake(moldtex_sim sim, const moldtex_bake_desc& d, std::string* message = nullptr) {
  moldtex_bake bake = nullptr;
  moldtex_status st = moldtex_bake_start(sim, &d, &bake);
  if (st != MOLDTEX_OK) return st;
  st = moldtex_bake_wait(bake);
  if (message) *message = LastError();
  moldtex_bake_release(bake);
  return st;
}

inline std::vector<char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace mtx

#endif  // MOLDTEX_TESTS_BAKE_UTIL_H

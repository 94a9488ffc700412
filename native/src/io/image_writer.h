// Writing the pheromone as image files through OpenImageIO (OpenEXR, PNG). A file is
// written under a temporary name in the same folder and renamed when complete, so a
// crash, kill or full disk never leaves a half-written frame under the final name.
#pragma once
#include <cstdint>
#include <string>

#include "moldtex.h"

namespace moldtex {

// `channels` planes of width*height floats interleaved per texel, rows bottom-up
// (Blender's order); names give one name per channel.
struct ImageData {
  uint32_t width = 0, height = 0, channels = 1;
  const float* texels = nullptr;
  const char* const* channel_names = nullptr;
};

void write_image_atomically(const std::string& path, const ImageData& image, moldtex_image_format format);

// Writes bytes to path through a temporary file and a rename (used for checkpoints and
// the metrics CSV too).
void write_file_atomically(const std::string& path, const void* data, size_t size);

}  // namespace moldtex

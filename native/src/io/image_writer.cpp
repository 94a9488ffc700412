#include "io/image_writer.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <vector>

#include "common/error.h"

namespace moldtex {

namespace {

// "frame_0001.exr" -> "frame_0001.exr.partial": not a frame name, so sequence loaders
// never pick it up; a resumed bake removes leftovers.
std::string temporary_name(const std::string& path) { return path + ".partial"; }

void commit(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(MOLDTEX_ERROR_IO, "Could not move the finished file into place as " + path + ": " + ec.message());
  }
}

}  // namespace

void write_file_atomically(const std::string& path, const void* data, size_t size) {
  const std::string tmp = temporary_name(path);
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) fail(MOLDTEX_ERROR_IO, "Could not create " + tmp + ": " + std::strerror(errno));
  bool ok = std::fwrite(data, 1, size, f) == size;
  ok = (std::fflush(f) == 0) && ok;
  ok = (std::fclose(f) == 0) && ok;
  if (!ok) {
    std::remove(tmp.c_str());
    fail(MOLDTEX_ERROR_IO, "Could not write " + path + " (is the disk full?)");
  }
  commit(tmp, path);
}

void write_image_atomically(const std::string& path, const ImageData& image, moldtex_image_format format) {
  OIIO::TypeDesc type = OIIO::TypeDesc::HALF;
  const char* plugin = "openexr";
  switch (format) {
    case MOLDTEX_IMAGE_EXR_HALF: break;
    case MOLDTEX_IMAGE_EXR_FLOAT: type = OIIO::TypeDesc::FLOAT; break;
    case MOLDTEX_IMAGE_PNG8: type = OIIO::TypeDesc::UINT8; plugin = "png"; break;
    case MOLDTEX_IMAGE_PNG16: type = OIIO::TypeDesc::UINT16; plugin = "png"; break;
    default: fail(MOLDTEX_ERROR_INVALID_ARGUMENT, "Unknown image format");
  }
  auto out = OIIO::ImageOutput::create(plugin);
  if (!out) fail(MOLDTEX_ERROR_IO, std::string("OpenImageIO cannot write ") + plugin + ": " + OIIO::geterror());
  OIIO::ImageSpec spec(static_cast<int>(image.width), static_cast<int>(image.height),
                       static_cast<int>(image.channels), type);
  spec.channelnames.clear();
  for (uint32_t c = 0; c < image.channels; ++c) spec.channelnames.emplace_back(image.channel_names[c]);
  if (plugin == std::string("openexr")) spec.attribute("compression", "zip");
  // OpenImageIO stamps the wall-clock time (EXR capDate) unless told otherwise; a fixed
  // stamp keeps frames a pure function of the simulation state, so a resumed bake
  // writes byte-identical files.
  spec.attribute("DateTime", "1970:01:01 00:00:00");
  const std::string tmp = temporary_name(path);
  if (!out->open(tmp, spec)) {
    std::string err = out->geterror();
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    fail(MOLDTEX_ERROR_IO, "Could not create " + path + ": " + err);
  }
  // Image files store the top row first; our rows are bottom-up, so start at the last
  // row and walk upward with a negative stride.
  const OIIO::stride_t pixel = static_cast<OIIO::stride_t>(image.channels * sizeof(float));
  const OIIO::stride_t row = pixel * image.width;
  const float* top = image.texels + static_cast<size_t>(image.height - 1) * image.width * image.channels;
  bool ok = out->write_image(OIIO::TypeDesc::FLOAT, top, pixel, -row);
  std::string err = ok ? "" : out->geterror();
  ok = out->close() && ok;
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    fail(MOLDTEX_ERROR_IO, "Could not write " + path + ": " + (err.empty() ? out->geterror() : err));
  }
  commit(tmp, path);
}

}  // namespace moldtex

// Reading linear images back: EXR (any channel, half or float or uint) and PFM, for
// --reference and for tests.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/io/exr_codec.h"
#include "src/io/image_io.h"

namespace pt {
namespace {

// tinyexr's own RGBA loader: handles tiled files and single-channel (Y or A) images.
void ReadExrRgbFallback(const std::string& path, int* width, int* height,
                        std::vector<float>* rgb) {
  float* rgba = nullptr;
  const char* err = nullptr;
  if (LoadEXR(&rgba, width, height, path.c_str(), &err) != TINYEXR_SUCCESS) {
    std::string message = path + ": cannot read EXR" + (err ? std::string(": ") + err : "");
    if (err) FreeEXRErrorMessage(err);
    throw ImageError(message);
  }
  size_t pixels = size_t(*width) * size_t(*height);
  rgb->resize(pixels * 3);
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) (*rgb)[i * 3 + c] = rgba[i * 4 + c];
  }
  std::free(rgba);
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageError(path + ": cannot open");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// Reads one whitespace-separated header token of a PFM file.
std::string PfmToken(const std::string& data, size_t* pos) {
  while (*pos < data.size() && std::isspace(static_cast<unsigned char>(data[*pos]))) ++*pos;
  size_t start = *pos;
  while (*pos < data.size() && !std::isspace(static_cast<unsigned char>(data[*pos]))) ++*pos;
  return data.substr(start, *pos - start);
}

float LoadFloat(const char* bytes, bool bigEndian) {
  uint32_t bits;
  std::memcpy(&bits, bytes, 4);
  if (bigEndian != (std::endian::native == std::endian::big)) bits = __builtin_bswap32(bits);
  return std::bit_cast<float>(bits);
}

}  // namespace

void ReadExrRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb) {
  ExrFile file(path);
  std::vector<float> planes[3];
  if (file.Tiled() || !file.Channel("R", &planes[0]) || !file.Channel("G", &planes[1]) ||
      !file.Channel("B", &planes[2])) {
    ReadExrRgbFallback(path, width, height, rgb);
    return;
  }
  *width = file.Width();
  *height = file.Height();
  size_t pixels = planes[0].size();
  rgb->resize(pixels * 3);
  for (size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 3; ++c) (*rgb)[i * 3 + c] = planes[c][i];
  }
}

std::vector<float> ReadExrChannel(const std::string& path, const std::string& name,
                                  int* width, int* height) {
  ExrFile file(path);
  std::vector<float> values;
  if (file.Tiled()) throw ImageError(path + ": tiled EXR channels are not supported");
  if (!file.Channel(name, &values)) throw ImageError(path + ": no channel '" + name + "'");
  *width = file.Width();
  *height = file.Height();
  return values;
}

void ReadPfmRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb) {
  std::string data = ReadWholeFile(path);
  size_t pos = 0;
  std::string magic = PfmToken(data, &pos);
  if (magic != "PF" && magic != "Pf") throw ImageError(path + ": not a PFM file");
  int channels = magic == "PF" ? 3 : 1;
  char* end = nullptr;
  std::string w = PfmToken(data, &pos), h = PfmToken(data, &pos), s = PfmToken(data, &pos);
  long wv = std::strtol(w.c_str(), &end, 10);
  bool ok = !w.empty() && *end == '\0';
  long hv = std::strtol(h.c_str(), &end, 10);
  ok = ok && !h.empty() && *end == '\0';
  double scale = std::strtod(s.c_str(), &end);
  ok = ok && !s.empty() && *end == '\0' && scale != 0.0 && wv > 0 && hv > 0 &&
       wv <= 1 << 16 && hv <= 1 << 16;
  if (!ok) throw ImageError(path + ": malformed PFM header");
  ++pos;  // exactly one whitespace byte ends the header
  size_t pixels = size_t(wv) * size_t(hv);
  if (data.size() < pos + pixels * channels * 4) throw ImageError(path + ": PFM data is short");
  bool bigEndian = scale > 0.0;
  rgb->resize(pixels * 3);
  for (long y = 0; y < hv; ++y) {
    const char* row = data.data() + pos + size_t(y) * size_t(wv) * channels * 4;
    float* out = rgb->data() + size_t(hv - 1 - y) * size_t(wv) * 3;  // bottom-to-top rows
    for (long x = 0; x < wv; ++x) {
      for (int c = 0; c < 3; ++c) {
        out[x * 3 + c] = LoadFloat(row + (size_t(x) * channels + (channels == 3 ? c : 0)) * 4,
                                   bigEndian);
      }
    }
  }
  *width = int(wv);
  *height = int(hv);
}

void ReadImageRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb) {
  ImageFormat format;
  if (!ImageFormatFromPath(path, &format) || format == ImageFormat::kPng) {
    throw ImageError(path + ": a linear image must be .exr or .pfm");
  }
  if (format == ImageFormat::kExr) ReadExrRgb(path, width, height, rgb);
  else ReadPfmRgb(path, width, height, rgb);
}

}  // namespace pt

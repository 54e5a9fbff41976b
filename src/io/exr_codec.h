// EXR files as the image writers and readers use them: planar channels and string header
// attributes out, a parsed scanline file in (tinyexr underneath).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <tinyexr.h>

#include "src/integrator/render_api.h"

namespace pt {

struct ExrChannel {
  std::string name;
  int pixelType;  // TINYEXR_PIXELTYPE_FLOAT or _UINT
  std::vector<uint8_t> data;  // width * height values of 4 bytes, rows top to bottom
};

// Component c of an interleaved array of `stride` floats per pixel, as a FLOAT channel.
ExrChannel FloatChannel(const std::string& name, const std::vector<float>& values, int stride,
                        int c);
// 32-bit words as a UINT channel (sample counts, or the bits of floats kept exactly).
ExrChannel UintChannel(const std::string& name, const std::vector<uint32_t>& words);

// R, G, B; with extras also variance.R/G/B, samples, albedo.R/G/B, normal.X/Y/Z, Z and
// denoised.R/G/B, each where the image has it.
std::vector<ExrChannel> ImageExrChannels(const FilmImage& image, bool withExtras);

struct ExrAttribute {
  std::string name, value;  // written as an OpenEXR "string" attribute
};

// The file's bytes: channels sorted by name as OpenEXR readers expect, ZIP compressed. Throws
// ImageError naming path on failure.
std::string EncodeExr(const std::string& path, int width, int height,
                      std::vector<ExrChannel> channels,
                      const std::vector<ExrAttribute>& attributes = {});

// A parsed scanline EXR, freed on every path out. Throws ImageError when unreadable.
class ExrFile {
 public:
  explicit ExrFile(const std::string& path);
  ~ExrFile();
  ExrFile(const ExrFile&) = delete;
  ExrFile& operator=(const ExrFile&) = delete;

  bool Tiled() const { return header_.tiled != 0 || image_.images == nullptr; }
  int Width() const { return image_.width; }
  int Height() const { return image_.height; }

  // The channel's pixels as floats (UINT converted), or false when there is no such channel.
  bool Channel(const std::string& name, std::vector<float>* out) const;
  // The channel's raw 32-bit words (FLOAT or UINT), or false when absent or half.
  bool Words(const std::string& name, std::vector<uint32_t>* out) const;
  // A string attribute's value, or false when the header has none of that name.
  bool Attribute(const std::string& name, std::string* value) const;

 private:
  int Find(const std::string& name) const;
  void Check(int status, const char* err);

  std::string path_;
  EXRHeader header_;
  EXRImage image_;
  bool headerParsed_ = false, imageLoaded_ = false;
};

}  // namespace pt

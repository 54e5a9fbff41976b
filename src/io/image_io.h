// Image files in and out: PNG (sRGB-encoded, clamped, 8-bit), EXR and PFM (linear floats).
// Every write goes to a temporary file beside the target and is renamed over it, so a failed
// or interrupted run never leaves a half-written image behind.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "src/integrator/render_api.h"

namespace pt {

// A file that cannot be read or written (the app maps it to exit status 2 or 3).
struct ImageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ImageFormat { kPng, kExr, kPfm };

// The format named by the path's extension (case-insensitive); false for any other.
bool ImageFormatFromPath(const std::string& path, ImageFormat* format);
bool IsExrPath(const std::string& path);
// The path's extension in lower case, with its dot (".exr"); empty when it has none.
std::string LowerExtension(const std::string& path);

// --spp-map: samples per pixel as a heat map (PNG) or raw counts (EXR, PFM).
void WriteSppMap(const std::string& path, const FilmImage& image);

// The sRGB OETF on one linear value, and its 8-bit code after clamping to [0, 1] (NaN -> 0):
// LinearToSrgb8 by a search of the code's thresholds, the same code as the reference's
// rounding of LinearToSrgb (tests/image_io_test.cpp checks it over every float's neighbourhood
// of each threshold and a dense sweep).
float LinearToSrgb(float linear);
uint8_t LinearToSrgb8(float linear);
uint8_t LinearToSrgb8Reference(float linear);

// Writes image.rgb in the format of the extension. With withExtras, an EXR also holds the
// per-pixel variance (variance.R/G/B) and sample-count (samples) channels when the image has
// them. Throws ImageError on an unknown extension, a size mismatch or any I/O failure.
void WriteImage(const std::string& path, const FilmImage& image, bool withExtras = false);

// The bytes WriteImage would write for this format; `name` is for messages.
std::string EncodeImage(const std::string& name, const FilmImage& image, ImageFormat format,
                        bool withExtras = false);

// 8-bit display pixels (`channels` a pixel: 3 RGB, 4 RGBA; rows top to bottom) as a PNG;
// `name` is for messages.
std::string EncodePng8(const std::string& name, int width, int height,
                       const std::vector<uint8_t>& pixels, int channels = 3);

// 8-bit sRGB pixels (3 a pixel, rows top to bottom) as a baseline JPEG of quality 1..100.
std::string EncodeJpeg(int width, int height, const std::vector<uint8_t>& srgb, int quality);

// Writes bytes to path through a temporary file in the same folder and a rename.
void WriteFileAtomic(const std::string& path, const std::string& bytes);

// Checks, before any rendering, that path's folder exists and a file can be created there
// (a probe file is created and removed; the target itself is left alone).
bool CheckWritable(const std::string& path, std::string* why);

// Linear RGB, rows top to bottom. Throw ImageError on a missing or malformed file.
void ReadExrRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb);
void ReadPfmRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb);
// Radiance .hdr (RGBE), through stb_image.
void ReadHdrRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb);
// By extension: .exr or .pfm.
void ReadImageRgb(const std::string& path, int* width, int* height, std::vector<float>* rgb);

// One named channel of an EXR file as floats (rows top to bottom); throws when absent.
std::vector<float> ReadExrChannel(const std::string& path, const std::string& name,
                                  int* width, int* height);

}  // namespace pt

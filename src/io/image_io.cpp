#include "src/io/image_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <cstdio>
#include <filesystem>

#include <zlib.h>

#include <thread>
#include <vector>

// PNG's deflate (issue 28: the image is written on the way to the user's first look at it):
// zlib at level 1 instead of stb's own compressor, which took 1.7-2.8x as long for a 30%
// larger file at 1080p, and cut into strips of 512 KiB (a 1080p image: 12) compressed on
// threads of their own, then joined into one zlib stream as pigz does (each strip a raw
// deflate ending byte-aligned by a sync flush, the last one final; the strips' Adler-32s
// combined). The strips depend on the size alone, so the file is the same on any machine.
static bool PtDeflateStrip(const unsigned char* data, size_t size, bool last, std::string* out) {
  z_stream s{};
  if (deflateInit2(&s, 1, Z_DEFLATED, -15, 8, Z_DEFAULT_STRATEGY) != Z_OK) return false;
  const size_t room = deflateBound(&s, uLong(size)) + 16;
  out->resize(room);
  s.next_in = const_cast<unsigned char*>(data);
  s.avail_in = uInt(size);
  s.next_out = reinterpret_cast<unsigned char*>(out->data());
  s.avail_out = uInt(room);
  const int status = deflate(&s, last ? Z_FINISH : Z_SYNC_FLUSH);
  out->resize(size_t(s.total_out));
  deflateEnd(&s);
  return last ? status == Z_STREAM_END : status == Z_OK && s.avail_in == 0;
}

static unsigned char* PtPngDeflate(unsigned char* data, int size, int* outSize, int) {
  constexpr size_t kStrip = size_t(1) << 19;
  const size_t bytes = size_t(size), strips = std::max<size_t>(1, (bytes + kStrip - 1) / kStrip);
  std::vector<std::string> parts(strips);
  std::vector<char> ok(strips, 0);
  const size_t threads =
      std::min<size_t>(strips, std::max(1u, std::thread::hardware_concurrency()));
  auto work = [&](size_t first) {
    for (size_t i = first; i < strips; i += threads) {
      const size_t begin = i * kStrip, end = std::min(bytes, begin + kStrip);
      ok[i] = PtDeflateStrip(data + begin, end - begin, i + 1 == strips, &parts[i]);
    }
  };
  std::vector<std::thread> pool;
  for (size_t t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (std::thread& t : pool) t.join();
  uLong adler = adler32(0L, Z_NULL, 0);
  size_t total = 6;
  for (size_t i = 0; i < strips; ++i) {
    if (!ok[i]) return nullptr;
    const size_t begin = i * kStrip, length = std::min(bytes, begin + kStrip) - begin;
    adler = adler32_combine(adler, adler32(1L, data + begin, uInt(length)), z_off_t(length));
    total += parts[i].size();
  }
  unsigned char* out = static_cast<unsigned char*>(std::malloc(total));
  if (!out) return nullptr;
  size_t at = 0;
  out[at++] = 0x78;  // deflate, 32K window; level 1's flags with a valid check
  out[at++] = 0x01;
  for (const std::string& part : parts) {
    std::memcpy(out + at, part.data(), part.size());
    at += part.size();
  }
  for (int shift = 24; shift >= 0; shift -= 8) out[at++] = (unsigned char)(adler >> shift);
  *outSize = int(at);
  return out;
}
#define STBIW_ZLIB_COMPRESS PtPngDeflate
// zlib's CRC-32 (sliced tables) for the chunks' checks instead of stb's byte loop: ~10 ms of a
// 1080p PNG's IDAT on one core.
#define STBIW_CRC32(buffer, len) uint32_t(crc32(0L, (buffer), uInt(len)))

// Static so that no other library's copy of stb_image_write can clash with this one.
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

#include "src/core/parallel_ranges.h"
#include "src/io/exr_codec.h"

namespace pt {
namespace {

namespace fs = std::filesystem;


std::string FolderOf(const std::string& path) {
  fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Creates a fresh file beside path (O_EXCL, so never someone else's); returns its fd.
int CreateTempBeside(const std::string& path, std::string* tempPath) {
  static std::atomic<uint64_t> counter{0};
  std::string base = FolderOf(path) + "/." + fs::path(path).filename().string() + ".tmp-" +
                     std::to_string(getpid()) + "-";
  for (int attempt = 0; attempt < 100; ++attempt) {
    *tempPath = base + std::to_string(counter++);
    int fd = open(tempPath->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  errno = EEXIST;
  return -1;
}

bool WriteAll(int fd, const char* data, size_t size) {
  while (size > 0) {
    ssize_t n = write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= size_t(n);
  }
  return true;
}

void CheckImageSize(const std::string& path, const FilmImage& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != size_t(image.width) * size_t(image.height) * 3) {
    throw ImageError(path + ": image size does not match its pixel data");
  }
}

std::string EncodePng(const std::string& path, const FilmImage& image) {
  // One filter for every row ("up": the row above subtracted), not stb's trial of all five
  // per row, which took a sixth to a fifth of the encoding for a 2.5% smaller file. Set once (threads
  // encode several PNGs at once).
  static const bool filterSet = (stbi_write_force_png_filter = 2, true);
  (void)filterSet;
  std::vector<uint8_t> bytes(image.rgb.size());
  ForRangesOnThreads(bytes.size(), 0, size_t(1) << 18, [&](size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) bytes[i] = LinearToSrgb8(image.rgb[i]);
  });
  return EncodePng8(path, image.width, image.height, bytes);
}

std::string EncodePfm(const FilmImage& image) {
  std::string out = "PF\n" + std::to_string(image.width) + " " +
                    std::to_string(image.height) + "\n-1.0\n";
  size_t rowBytes = size_t(image.width) * 3 * sizeof(float);
  size_t header = out.size();
  out.resize(header + rowBytes * size_t(image.height));
  // PFM rows run bottom to top; floats are little-endian (scale -1), as on every host we target.
  static_assert(std::endian::native == std::endian::little, "PFM writer assumes little-endian");
  for (int y = 0; y < image.height; ++y) {
    const float* row = image.rgb.data() + size_t(image.height - 1 - y) * image.width * 3;
    std::memcpy(out.data() + header + size_t(y) * rowBytes, row, rowBytes);
  }
  return out;
}

std::string EncodeImageExr(const std::string& path, const FilmImage& image, bool withExtras) {
  return EncodeExr(path, image.width, image.height, ImageExrChannels(image, withExtras));
}

}  // namespace

std::string LowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

bool IsExrPath(const std::string& path) { return LowerExtension(path) == ".exr"; }

// A heat map of samples per pixel: PNG through a perceptual ramp scaled to the largest count
// (the legend is in the stats: spp_mean); EXR or PFM keep the raw counts as grey values.
void WriteSppMap(const std::string& path, const FilmImage& image) {
  FilmImage map = image;
  size_t pixels = size_t(image.width) * image.height;
  uint32_t most = 1;
  for (uint32_t n : image.samples) most = std::max(most, n);
  ImageFormat format;
  bool png = ImageFormatFromPath(path, &format) && format == ImageFormat::kPng;
  // Viridis at five stops, in linear RGB so the PNG encoder's sRGB curve restores them.
  static const float kRamp[5][3] = {{0.267f, 0.005f, 0.329f}, {0.231f, 0.322f, 0.546f},
                                    {0.128f, 0.567f, 0.551f}, {0.369f, 0.789f, 0.383f},
                                    {0.993f, 0.906f, 0.144f}};
  for (size_t i = 0; i < pixels; ++i) {
    float t = float(image.samples[i]) / float(most);
    for (int c = 0; c < 3; ++c) {
      float v = float(image.samples[i]);
      if (png) {
        float x = t * 4.0f;
        int k = std::min(3, int(x));
        float srgb = kRamp[k][c] + (x - k) * (kRamp[k + 1][c] - kRamp[k][c]);
        v = srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f);
      }
      map.rgb[3 * i + c] = v;
    }
  }
  map.albedo.clear();
  WriteImage(path, map, false);
}

bool ImageFormatFromPath(const std::string& path, ImageFormat* format) {
  std::string ext = LowerExtension(path);
  if (ext == ".png") *format = ImageFormat::kPng;
  else if (ext == ".exr") *format = ImageFormat::kExr;
  else if (ext == ".pfm") *format = ImageFormat::kPfm;
  else return false;
  return true;
}

float LinearToSrgb(float linear) {
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

uint8_t LinearToSrgb8Reference(float linear) {
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  return uint8_t(std::lround(std::clamp(LinearToSrgb(linear), 0.0f, 1.0f) * 255.0f));
}

namespace {

// For code k (1-255) the smallest positive float whose reference code is at least k, found by
// bisection over the bit patterns (positive floats order as their patterns do): the code is
// then the number of thresholds at or below the value. A 1080p PNG spent ~50 ms in pow and
// lround on one core; the search takes 8 comparisons.
struct SrgbThresholds {
  float at[256];
  SrgbThresholds() {
    at[0] = 0.0f;
    for (int k = 1; k < 256; ++k) {
      uint32_t lo = 0, hi = std::bit_cast<uint32_t>(1.0f);  // code(lo) < k <= code(hi)
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (LinearToSrgb8Reference(std::bit_cast<float>(mid)) >= k ? hi : lo) = mid;
      }
      at[k] = std::bit_cast<float>(hi);
    }
  }
};

}  // namespace

uint8_t LinearToSrgb8(float linear) {
  static const SrgbThresholds thresholds;
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  uint32_t code = 0;
  for (uint32_t step = 128; step > 0; step >>= 1)
    if (thresholds.at[code + step] <= linear) code += step;
  return uint8_t(code);
}

void WriteFileAtomic(const std::string& path, const std::string& bytes) {
  std::string temp;
  int fd = CreateTempBeside(path, &temp);
  if (fd < 0) throw ImageError(path + ": cannot create a file there: " + std::strerror(errno));
  bool ok = WriteAll(fd, bytes.data(), bytes.size());
  int savedErrno = errno;
  if (close(fd) != 0 && ok) {
    ok = false;
    savedErrno = errno;
  }
  if (ok && std::rename(temp.c_str(), path.c_str()) != 0) {
    ok = false;
    savedErrno = errno;
  }
  if (!ok) {
    unlink(temp.c_str());
    throw ImageError(path + ": write failed: " + std::strerror(savedErrno));
  }
}

std::string EncodeImage(const std::string& name, const FilmImage& image, ImageFormat format,
                        bool withExtras) {
  CheckImageSize(name, image);
  switch (format) {
    case ImageFormat::kPng: return EncodePng(name, image);
    case ImageFormat::kExr: return EncodeImageExr(name, image, withExtras);
    case ImageFormat::kPfm: return EncodePfm(image);
  }
  throw ImageError(name + ": unknown image format");
}

std::string EncodePng8(const std::string& name, int width, int height,
                       const std::vector<uint8_t>& pixels, int channels) {
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixels.size() != size_t(width) * size_t(height) * size_t(channels)) {
    throw ImageError(name + ": image size does not match its pixel data");
  }
  std::string out;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_png_to_func(append, &out, width, height, channels, pixels.data(),
                              width * channels)) {
    throw ImageError(name + ": PNG encoding failed");
  }
  return out;
}

std::string EncodeJpeg(int width, int height, const std::vector<uint8_t>& srgb, int quality) {
  if (width <= 0 || height <= 0 || srgb.size() != size_t(width) * size_t(height) * 3) {
    throw ImageError("JPEG: image size does not match its pixel data");
  }
  std::string out;
  auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size));
  };
  if (!stbi_write_jpg_to_func(append, &out, width, height, 3, srgb.data(), quality)) {
    throw ImageError("JPEG encoding failed");
  }
  return out;
}

void WriteImage(const std::string& path, const FilmImage& image, bool withExtras) {
  ImageFormat format;
  if (!ImageFormatFromPath(path, &format)) {
    throw ImageError(path + ": unknown image extension (use .png, .exr or .pfm)");
  }
  WriteFileAtomic(path, EncodeImage(path, image, format, withExtras));
}

bool CheckWritable(const std::string& path, std::string* why) {
  std::string folder = FolderOf(path);
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    if (why) *why = "the folder " + folder + " does not exist";
    return false;
  }
  if (fs::is_directory(path, ec)) {
    if (why) *why = path + " is a folder";
    return false;
  }
  std::string probe;
  int fd = CreateTempBeside(path, &probe);
  if (fd < 0) {
    if (why) *why = "cannot create a file in " + folder + ": " + std::strerror(errno);
    return false;
  }
  close(fd);
  unlink(probe.c_str());
  return true;
}

}  // namespace pt

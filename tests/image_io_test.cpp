// Image files: PNG sRGB encoding, EXR and PFM round trips (PFM row order, endianness and
// scale), atomic writes that leave nothing behind on failure, and the writability probe.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "src/io/image_io.h"
#include "tests/test_util.h"

// Static so that no other copy of stb_image in the test binary can clash with this one.
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace pt {
namespace {

namespace fs = std::filesystem;

// A small image whose every value differs, so that row or channel swaps show.
FilmImage TestImage(int width, int height) {
  FilmImage image;
  image.width = width;
  image.height = height;
  size_t pixels = size_t(width) * height;
  for (size_t i = 0; i < pixels * 3; ++i) image.rgb.push_back(0.01f * float(i) + 0.125f);
  for (size_t i = 0; i < pixels * 3; ++i) image.variance.push_back(0.5f * float(i));
  for (size_t i = 0; i < pixels; ++i) image.samples.push_back(uint32_t(10 + i));
  return image;
}

size_t EntryCount(const std::string& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(ImageIo, SrgbEncodingOfKnownValues) {
  EXPECT_FLOAT_EQ(LinearToSrgb(0.0f), 0.0f);
  EXPECT_NEAR(LinearToSrgb(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(LinearToSrgb(0.0031308f), 0.04045f, 1e-5f);  // the knee of the curve
  EXPECT_NEAR(LinearToSrgb(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(LinearToSrgb(0.001f), 0.01292f, 1e-6f);       // linear segment
  EXPECT_EQ(LinearToSrgb8(0.0f), 0);
  EXPECT_EQ(LinearToSrgb8(1.0f), 255);
  EXPECT_EQ(LinearToSrgb8(0.5f), 188);
  EXPECT_EQ(LinearToSrgb8(0.18f), 118);  // middle grey
  EXPECT_EQ(LinearToSrgb8(0.2158605f), 128);  // exactly code 128
  // Clamped, and a NaN never reaches the file as garbage.
  EXPECT_EQ(LinearToSrgb8(7.5f), 255);
  EXPECT_EQ(LinearToSrgb8(-2.0f), 0);
  EXPECT_EQ(LinearToSrgb8(std::numeric_limits<float>::infinity()), 255);
  EXPECT_EQ(LinearToSrgb8(std::nanf("")), 0);
}

// The threshold search gives the reference's code (pow, then rounding) for every float: a
// sweep of every 61st bit pattern from 0 to 1, and wherever two sampled neighbours differ in
// code, every pattern between them (so each of the 255 steps is checked float by float).
// Negative values, -0, denormals, NaN and infinities too.
TEST(ImageIo, SrgbCodeSearchMatchesTheReferenceForEveryFloatNearEachStep) {
  constexpr uint32_t kStride = 61, kOne = 0x3F800000u;
  int steps = 0;
  uint8_t previous = LinearToSrgb8Reference(0.0f);
  for (uint32_t bits = 0; bits <= kOne; bits += kStride) {
    const float x = std::bit_cast<float>(bits);
    const uint8_t code = LinearToSrgb8Reference(x);
    ASSERT_EQ(LinearToSrgb8(x), code) << x;
    if (code != previous) {
      ++steps;
      for (uint32_t b = bits - kStride + 1; b < bits; ++b) {
        const float y = std::bit_cast<float>(b);
        ASSERT_EQ(LinearToSrgb8(y), LinearToSrgb8Reference(y)) << y;
      }
    }
    previous = code;
  }
  EXPECT_EQ(steps, 255);
  for (float x : {-0.0f, -1e-30f, std::numeric_limits<float>::denorm_min(), 1e-40f, 1.0f,
                  std::nextafter(1.0f, 0.0f), 1e30f, -std::numeric_limits<float>::infinity(),
                  std::numeric_limits<float>::infinity(), std::nanf("")})
    EXPECT_EQ(LinearToSrgb8(x), LinearToSrgb8Reference(x)) << x;
}

TEST(ImageIo, PngRoundTripIsSrgbEncodedTopToBottom) {
  std::string path = test::TempDir() + "/out.png";
  FilmImage image = TestImage(4, 3);
  image.rgb[0] = 2.0f;   // clamped
  image.rgb[1] = -1.0f;  // clamped
  image.rgb[2] = 0.5f;
  WriteImage(path, image);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 0);
  ASSERT_NE(data, nullptr);
  EXPECT_EQ(w, 4);
  EXPECT_EQ(h, 3);
  EXPECT_EQ(channels, 3);
  EXPECT_EQ(data[0], 255);
  EXPECT_EQ(data[1], 0);
  EXPECT_EQ(data[2], 188);
  for (size_t i = 0; i < image.rgb.size(); ++i) {
    EXPECT_EQ(data[i], LinearToSrgb8(image.rgb[i])) << "value " << i;
  }
  stbi_image_free(data);
}

// The PNG's deflate is zlib's at level 1 (image_io.cpp): a large image of noise and smooth
// ramps (stored, filtered and matched blocks all occur) decodes to exactly its sRGB bytes.
TEST(ImageIo, PngOfALargeNoisyImageDecodesExactly) {
  std::string path = test::TempDir() + "/big.png";
  FilmImage image;
  image.width = 517;
  image.height = 261;
  uint32_t state = 12345u;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width * 3; ++x) {
      state = state * 1664525u + 1013904223u;
      const float noise = float(state >> 8) * 0x1p-24f;
      image.rgb.push_back(y < image.height / 2 ? noise : float(x) / float(image.width * 3));
    }
  }
  WriteImage(path, image);
  int w = 0, h = 0, channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &w, &h, &channels, 3);
  ASSERT_NE(data, nullptr);
  ASSERT_EQ(w, image.width);
  ASSERT_EQ(h, image.height);
  size_t wrong = 0;
  for (size_t i = 0; i < image.rgb.size(); ++i) wrong += data[i] != LinearToSrgb8(image.rgb[i]);
  EXPECT_EQ(wrong, 0u);
  stbi_image_free(data);
}

TEST(ImageIo, ExrRoundTripKeepsFloatsAndExtraChannels) {
  std::string path = test::TempDir() + "/out.exr";
  FilmImage image = TestImage(5, 3);
  image.rgb[4] = 1234.5f;  // HDR values survive
  WriteImage(path, image, true);
  int w = 0, h = 0;
  std::vector<float> rgb;
  ReadExrRgb(path, &w, &h, &rgb);
  EXPECT_EQ(w, 5);
  EXPECT_EQ(h, 3);
  EXPECT_EQ(rgb, image.rgb);
  std::vector<float> samples = ReadExrChannel(path, "samples", &w, &h);
  ASSERT_EQ(samples.size(), image.samples.size());
  for (size_t i = 0; i < samples.size(); ++i) EXPECT_EQ(samples[i], float(image.samples[i]));
  const char* names[] = {"variance.R", "variance.G", "variance.B"};
  for (int c = 0; c < 3; ++c) {
    std::vector<float> variance = ReadExrChannel(path, names[c], &w, &h);
    ASSERT_EQ(variance.size(), image.samples.size());
    for (size_t i = 0; i < variance.size(); ++i) EXPECT_EQ(variance[i], image.variance[i * 3 + c]);
  }
}

TEST(ImageIo, ExrWithoutExtrasHoldsOnlyRgb) {
  std::string path = test::TempDir() + "/out.EXR";
  FilmImage image = TestImage(2, 2);
  WriteImage(path, image, false);
  int w = 0, h = 0;
  EXPECT_THROW(ReadExrChannel(path, "samples", &w, &h), ImageError);
  std::vector<float> r = ReadExrChannel(path, "R", &w, &h);
  EXPECT_EQ(r[3], image.rgb[9]);
}

TEST(ImageIo, PfmRoundTrip) {
  std::string path = test::TempDir() + "/out.pfm";
  FilmImage image = TestImage(7, 4);
  image.rgb[5] = -3.0f;
  image.rgb[6] = 1e6f;
  WriteImage(path, image);
  int w = 0, h = 0;
  std::vector<float> rgb;
  ReadPfmRgb(path, &w, &h, &rgb);
  EXPECT_EQ(w, 7);
  EXPECT_EQ(h, 4);
  EXPECT_EQ(rgb, image.rgb);
  ReadImageRgb(path, &w, &h, &rgb);  // by extension
  EXPECT_EQ(rgb, image.rgb);
}

TEST(ImageIo, PfmIsBottomToTopLittleEndianScaleMinusOne) {
  std::string path = test::TempDir() + "/out.pfm";
  FilmImage image = TestImage(3, 2);
  WriteImage(path, image);
  std::string bytes = test::ReadText(path);
  std::string header = "PF\n3 2\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 3 * 2 * 3 * 4);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + header.size();
  // The file's first row is the image's bottom row (row 1), floats little-endian.
  for (int i = 0; i < 9; ++i) {
    uint32_t bits = uint32_t(data[i * 4]) | uint32_t(data[i * 4 + 1]) << 8 |
                    uint32_t(data[i * 4 + 2]) << 16 | uint32_t(data[i * 4 + 3]) << 24;
    float value;
    std::memcpy(&value, &bits, 4);
    EXPECT_EQ(value, image.rgb[9 + i]) << "value " << i;
  }
}

TEST(ImageIo, PfmReadsBigEndianAndGreyscale) {
  std::string path = test::TempDir() + "/grey.pfm";
  std::string bytes = "Pf\n2 2\n1.0\n";
  float values[] = {1.0f, 2.0f, 3.0f, 4.0f};  // rows bottom to top
  for (float v : values) {
    uint32_t bits;
    std::memcpy(&bits, &v, 4);
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(char((bits >> shift) & 0xff));
  }
  std::ofstream(path, std::ios::binary) << bytes;
  int w = 0, h = 0;
  std::vector<float> rgb;
  ReadPfmRgb(path, &w, &h, &rgb);
  ASSERT_EQ(rgb.size(), 12u);
  std::vector<float> expected = {3, 3, 3, 4, 4, 4, 1, 1, 1, 2, 2, 2};
  EXPECT_EQ(rgb, expected);
}

TEST(ImageIo, FormatFollowsExtensionCaseInsensitive) {
  ImageFormat format;
  ASSERT_TRUE(ImageFormatFromPath("a/b.PNG", &format));
  EXPECT_EQ(format, ImageFormat::kPng);
  ASSERT_TRUE(ImageFormatFromPath("b.Exr", &format));
  EXPECT_EQ(format, ImageFormat::kExr);
  ASSERT_TRUE(ImageFormatFromPath("c.pFm", &format));
  EXPECT_EQ(format, ImageFormat::kPfm);
  EXPECT_FALSE(ImageFormatFromPath("d.jpg", &format));
  EXPECT_FALSE(ImageFormatFromPath("png", &format));
  std::string dir = test::TempDir();
  EXPECT_THROW(WriteImage(dir + "/x.tga", TestImage(2, 2)), ImageError);
  EXPECT_EQ(EntryCount(dir), 0u);
}

TEST(ImageIo, FailedWriteLeavesNoFileAndKeepsTheOldOne) {
  std::string dir = test::TempDir();
  FilmImage bad = TestImage(4, 4);
  bad.rgb.pop_back();  // size mismatch
  EXPECT_THROW(WriteImage(dir + "/new.png", bad), ImageError);
  EXPECT_EQ(EntryCount(dir), 0u);

  std::string old = dir + "/old.pfm";
  std::ofstream(old) << "old";
  EXPECT_THROW(WriteImage(old, bad), ImageError);
  EXPECT_EQ(test::ReadText(old), "old");

  // A rename that fails (the target is a folder) removes its temporary file.
  fs::create_directory(dir + "/folder.exr");
  EXPECT_THROW(WriteImage(dir + "/folder.exr", TestImage(2, 2)), ImageError);
  EXPECT_EQ(EntryCount(dir), 2u);  // old.pfm and folder.exr, no temporary file

  // A folder that does not exist.
  EXPECT_THROW(WriteImage(dir + "/missing/out.png", TestImage(2, 2)), ImageError);
}

TEST(ImageIo, WriteReplacesAnExistingFile) {
  std::string dir = test::TempDir();
  std::string path = dir + "/out.pfm";
  std::ofstream(path) << "old contents";
  WriteImage(path, TestImage(2, 2));
  EXPECT_EQ(test::ReadText(path).substr(0, 3), "PF\n");
  EXPECT_EQ(EntryCount(dir), 1u);
}

TEST(ImageIo, CheckWritableOnAMissingFolder) {
  std::string dir = test::TempDir();
  std::string why;
  EXPECT_FALSE(CheckWritable(dir + "/no/such/folder/out.png", &why));
  EXPECT_NE(why.find("does not exist"), std::string::npos) << why;
  EXPECT_FALSE(CheckWritable(dir, &why));  // the target is a folder
}

TEST(ImageIo, CheckWritableLeavesTheFolderAsItWas) {
  std::string dir = test::TempDir();
  std::string why;
  EXPECT_TRUE(CheckWritable(dir + "/out.png", &why)) << why;
  EXPECT_EQ(EntryCount(dir), 0u);
  std::string existing = dir + "/kept.exr";
  std::ofstream(existing) << "kept";
  EXPECT_TRUE(CheckWritable(existing, &why)) << why;
  EXPECT_EQ(test::ReadText(existing), "kept");
  EXPECT_EQ(EntryCount(dir), 1u);
}

TEST(ImageIo, CheckWritableOnAReadOnlyFolder) {
  if (geteuid() == 0) GTEST_SKIP() << "root can write anywhere";
  std::string dir = test::TempDir();
  chmod(dir.c_str(), 0555);
  std::string why;
  EXPECT_FALSE(CheckWritable(dir + "/out.png", &why));
  EXPECT_FALSE(why.empty());
  chmod(dir.c_str(), 0755);
}

TEST(ImageIo, ReadingMissingOrMalformedFilesThrows) {
  std::string dir = test::TempDir();
  int w = 0, h = 0;
  std::vector<float> rgb;
  EXPECT_THROW(ReadExrRgb(dir + "/missing.exr", &w, &h, &rgb), ImageError);
  EXPECT_THROW(ReadPfmRgb(dir + "/missing.pfm", &w, &h, &rgb), ImageError);
  std::ofstream(dir + "/bad.pfm") << "PF\n3 x\n-1.0\n";
  EXPECT_THROW(ReadPfmRgb(dir + "/bad.pfm", &w, &h, &rgb), ImageError);
  std::ofstream(dir + "/short.pfm") << "PF\n3 2\n-1.0\nabc";
  EXPECT_THROW(ReadPfmRgb(dir + "/short.pfm", &w, &h, &rgb), ImageError);
  std::ofstream(dir + "/bad.exr") << "not an exr";
  EXPECT_THROW(ReadExrRgb(dir + "/bad.exr", &w, &h, &rgb), ImageError);
  EXPECT_THROW(ReadImageRgb(dir + "/x.png", &w, &h, &rgb), ImageError);
}

}  // namespace
}  // namespace pt

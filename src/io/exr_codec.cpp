#include "src/io/exr_codec.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "src/io/image_io.h"

namespace pt {

ExrChannel FloatChannel(const std::string& name, const std::vector<float>& values, int stride,
                        int c) {
  size_t pixels = values.size() / size_t(stride);
  ExrChannel ch{name, TINYEXR_PIXELTYPE_FLOAT, std::vector<uint8_t>(pixels * 4)};
  float* out = reinterpret_cast<float*>(ch.data.data());
  for (size_t i = 0; i < pixels; ++i) out[i] = values[i * size_t(stride) + size_t(c)];
  return ch;
}

ExrChannel UintChannel(const std::string& name, const std::vector<uint32_t>& words) {
  ExrChannel ch{name, TINYEXR_PIXELTYPE_UINT, std::vector<uint8_t>(words.size() * 4)};
  if (!words.empty()) std::memcpy(ch.data.data(), words.data(), words.size() * 4);
  return ch;
}

// The image, and with extras its variance, sample-count and feature channels where present.
std::vector<ExrChannel> ImageExrChannels(const FilmImage& image, bool withExtras) {
  std::vector<ExrChannel> channels;
  for (int c = 0; c < 3; ++c) {
    channels.push_back(FloatChannel(std::string(1, "RGB"[c]), image.rgb, 3, c));
  }
  if (!withExtras) return channels;
  size_t pixels = size_t(image.width) * image.height;
  if (image.samples.size() == pixels) channels.push_back(UintChannel("samples", image.samples));
  if (image.variance.size() == pixels * 3) {
    for (int c = 0; c < 3; ++c) {
      channels.push_back(FloatChannel(std::string("variance.") + "RGB"[c], image.variance, 3, c));
    }
  }
  // First-hit feature buffers for denoisers (albedo, normal) and the hit distance as Z.
  if (image.albedo.size() == pixels * 3) {
    for (int c = 0; c < 3; ++c) {
      channels.push_back(FloatChannel(std::string("albedo.") + "RGB"[c], image.albedo, 3, c));
      channels.push_back(FloatChannel(std::string("normal.") + "XYZ"[c], image.normal, 3, c));
    }
    channels.push_back(FloatChannel("Z", image.depth, 1, 0));
  }
  if (image.denoised.size() == pixels * 3) {  // --denoise's image beside the raw one
    for (int c = 0; c < 3; ++c) {
      channels.push_back(FloatChannel(std::string("denoised.") + "RGB"[c], image.denoised, 3, c));
    }
  }
  return channels;
}

std::string EncodeExr(const std::string& path, int width, int height,
                      std::vector<ExrChannel> channels,
                      const std::vector<ExrAttribute>& attributes) {
  std::sort(channels.begin(), channels.end(),
            [](const ExrChannel& a, const ExrChannel& b) { return a.name < b.name; });
  std::vector<EXRChannelInfo> infos(channels.size());
  std::vector<int> types(channels.size());
  std::vector<unsigned char*> planes(channels.size());
  for (size_t i = 0; i < channels.size(); ++i) {
    std::memset(&infos[i], 0, sizeof(EXRChannelInfo));
    std::snprintf(infos[i].name, sizeof(infos[i].name), "%s", channels[i].name.c_str());
    types[i] = channels[i].pixelType;
    planes[i] = channels[i].data.data();
  }
  std::vector<EXRAttribute> extra(attributes.size());
  for (size_t i = 0; i < attributes.size(); ++i) {
    std::memset(&extra[i], 0, sizeof(EXRAttribute));
    std::snprintf(extra[i].name, sizeof(extra[i].name), "%s", attributes[i].name.c_str());
    std::snprintf(extra[i].type, sizeof(extra[i].type), "string");
    extra[i].value =
        reinterpret_cast<unsigned char*>(const_cast<char*>(attributes[i].value.data()));
    extra[i].size = int(attributes[i].value.size());
  }
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = int(channels.size());
  header.channels = infos.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  // Uncompressed (issue 28): a render's float channels are noise to a compressor, which saved
  // 10% (ZIP) to 21% (PIZ) of a 1080p EXR of 14 channels for 19-23x (ZIP) or 8-9x (PIZ) the
  // time of writing it plain (benchmarks/RESULTS.md); the image waits on it at a run's end.
  header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE;
  header.num_custom_attributes = int(extra.size());
  header.custom_attributes = extra.empty() ? nullptr : extra.data();
  EXRImage exr;
  InitEXRImage(&exr);
  exr.num_channels = int(channels.size());
  exr.images = planes.data();
  exr.width = width;
  exr.height = height;
  unsigned char* memory = nullptr;
  const char* err = nullptr;
  size_t size = SaveEXRImageToMemory(&exr, &header, &memory, &err);
  if (size == 0) {
    std::string message = path + ": EXR encoding failed" + (err ? std::string(": ") + err : "");
    if (err) FreeEXRErrorMessage(err);
    throw ImageError(message);
  }
  std::string out(reinterpret_cast<char*>(memory), size);
  std::free(memory);
  return out;
}

ExrFile::ExrFile(const std::string& path) : path_(path) {
  InitEXRHeader(&header_);
  InitEXRImage(&image_);
  EXRVersion version;
  if (ParseEXRVersionFromFile(&version, path.c_str()) != TINYEXR_SUCCESS) {
    throw ImageError(path + ": not a readable EXR file");
  }
  if (version.multipart || version.non_image) {
    throw ImageError(path + ": multi-part and deep EXR files are not supported");
  }
  // The status first, then err: as two arguments of one call their order is unspecified, and
  // err read before the call was null (the message lost, the string leaked).
  const char* err = nullptr;
  int status = ParseEXRHeaderFromFile(&header_, &version, path.c_str(), &err);
  if (status != TINYEXR_SUCCESS) FreeEXRHeader(&header_);  // tinyexr fills it even on failure
  Check(status, err);
  headerParsed_ = true;
  for (int i = 0; i < header_.num_channels; ++i) {
    if (header_.pixel_types[i] == TINYEXR_PIXELTYPE_HALF) {
      header_.requested_pixel_types[i] = TINYEXR_PIXELTYPE_FLOAT;
    }
  }
  err = nullptr;
  status = LoadEXRImageFromFile(&image_, &header_, path.c_str(), &err);
  if (status != TINYEXR_SUCCESS) FreeEXRHeader(&header_);  // a throwing constructor: no destructor
  Check(status, err);
  imageLoaded_ = true;
}

ExrFile::~ExrFile() {
  if (imageLoaded_) FreeEXRImage(&image_);
  if (headerParsed_) FreeEXRHeader(&header_);
}

int ExrFile::Find(const std::string& name) const {
  for (int c = 0; c < header_.num_channels; ++c) {
    if (name == header_.channels[c].name) return c;
  }
  return -1;
}

bool ExrFile::Words(const std::string& name, std::vector<uint32_t>* out) const {
  int c = Find(name);
  if (c < 0 || Tiled()) return false;
  size_t pixels = size_t(image_.width) * size_t(image_.height);
  out->resize(pixels);
  if (pixels) std::memcpy(out->data(), image_.images[c], pixels * 4);
  return true;
}

bool ExrFile::Channel(const std::string& name, std::vector<float>* out) const {
  std::vector<uint32_t> words;
  if (!Words(name, &words)) return false;
  bool isUint = header_.pixel_types[Find(name)] == TINYEXR_PIXELTYPE_UINT;
  out->resize(words.size());
  for (size_t i = 0; i < words.size(); ++i) {
    if (isUint) (*out)[i] = float(words[i]);
    else std::memcpy(&(*out)[i], &words[i], 4);
  }
  return true;
}

bool ExrFile::Attribute(const std::string& name, std::string* value) const {
  for (int i = 0; i < header_.num_custom_attributes; ++i) {
    const EXRAttribute& a = header_.custom_attributes[i];
    if (name != a.name) continue;
    value->assign(reinterpret_cast<const char*>(a.value), size_t(std::max(a.size, 0)));
    return true;
  }
  return false;
}

void ExrFile::Check(int status, const char* err) {
  if (status == TINYEXR_SUCCESS) return;
  std::string message = path_ + ": cannot read EXR" + (err ? std::string(": ") + err : "");
  if (err) FreeEXRErrorMessage(err);
  throw ImageError(message);
}

}  // namespace pt

// The selection outline the page lays over the image: the selected object's silhouette edge,
// found by casting the pick ray through every pixel of a reduced grid (the render's own
// traversal on the host), as an RGBA PNG whose other pixels are transparent.
#include <algorithm>
#include <cmath>

#include "src/io/image_io.h"
#include "src/server/live_render.h"

namespace pt {
namespace {

constexpr uint8_t kOutline[4] = {255, 170, 40, 255};  // orange, opaque
constexpr uint8_t kFill[4] = {255, 170, 40, 40};      // the object itself, faintly

}  // namespace

std::string LiveRender::OutlinePng(int maxSide) const {
  int object;
  {
    std::lock_guard<std::mutex> lock(docMutex_);
    object = selectedObject_;
  }
  if (object < 0) return "";
  float scale = std::min(1.0f, float(std::max(1, maxSide)) / float(std::max(width_, height_)));
  int w = std::max(1, int(std::lround(width_ * scale)));
  int h = std::max(1, int(std::lround(height_ * scale)));
  std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
  {
    std::shared_lock<std::shared_mutex> lock(sceneMutex_);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        float px = (float(x) + 0.5f) * float(width_) / float(w);
        float py = (float(y) + 0.5f) * float(height_) / float(h);
        PickResult hit = PickPixel(scene_, camera_, width_, height_, px, py, objects_);
        mask[size_t(y) * size_t(w) + size_t(x)] = hit.object == object ? 1 : 0;
      }
    }
  }
  // An edge pixel is in the object and has a 4-neighbour outside it (or the image's border).
  std::vector<uint8_t> rgba(mask.size() * 4, 0);
  auto in = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && mask[size_t(y) * size_t(w) + size_t(x)];
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (!in(x, y)) continue;
      bool edge = !in(x - 1, y) || !in(x + 1, y) || !in(x, y - 1) || !in(x, y + 1);
      const uint8_t* color = edge ? kOutline : kFill;
      std::copy(color, color + 4, rgba.begin() + std::ptrdiff_t(4 * (size_t(y) * w + x)));
    }
  }
  return EncodePng8("the outline", w, h, rgba, 4);
}

}  // namespace pt

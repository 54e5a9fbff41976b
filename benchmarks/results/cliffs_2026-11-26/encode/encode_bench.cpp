#include <zlib.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
#include <random>
#include <cmath>
static unsigned char* Deflate1(unsigned char* data, int size, int* outSize, int) {
  uLongf bound = compressBound(uLong(size));
  unsigned char* out = (unsigned char*)malloc(bound);
  if (compress2(out, &bound, data, uLong(size), 1) != Z_OK) { free(out); return nullptr; }
  *outSize = int(bound); return out;
}
#ifdef USE_ZLIB
#define STBIW_ZLIB_COMPRESS Deflate1
#endif
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>
#include <tinyexr.h>
using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point t){return std::chrono::duration<double,std::milli>(Clock::now()-t).count();}
int main() {
  const int W = 1920, H = 1080;
  std::mt19937 rng(1); std::normal_distribution<float> g(0.f, 0.05f);
  std::vector<float> rgb(size_t(W)*H*3);
  for (int y=0;y<H;++y) for (int x=0;x<W;++x) for(int c=0;c<3;++c)
    rgb[(size_t(y)*W+x)*3+c] = std::max(0.f, 0.4f + 0.3f*std::sin(x*0.01f+c)*std::cos(y*0.013f) + g(rng));
  std::vector<unsigned char> bytes(rgb.size());
  for (size_t i=0;i<rgb.size();++i) bytes[i] = (unsigned char)std::min(255.f, 255.f*std::pow(rgb[i],1/2.2f));
  std::string out; auto app=[](void* c, void* d, int s){((std::string*)c)->append((char*)d, s);};
  for (int f : {-1, 0, 1, 2, 4}) {
    stbi_write_force_png_filter = f; out.clear();
    auto t=Clock::now(); stbi_write_png_to_func(app, &out, W, H, 3, bytes.data(), W*3);
    printf("png filter %d: %.1f ms %.2f MB\n", f, Ms(t), out.size()/1e6);
  }
  // EXR: 14 float channels
  int nch = 14; std::vector<std::vector<float>> planes(nch, std::vector<float>(size_t(W)*H));
  for (int c=0;c<nch;++c) for (size_t i=0;i<size_t(W)*H;++i) planes[c][i] = c<3 ? rgb[i*3+c] : (c==3? 64.f : rgb[i*3+(c%3)]*0.5f + g(rng)*0.1f);
  for (int comp : {TINYEXR_COMPRESSIONTYPE_NONE, TINYEXR_COMPRESSIONTYPE_ZIPS, TINYEXR_COMPRESSIONTYPE_ZIP, TINYEXR_COMPRESSIONTYPE_PIZ}) {
    EXRHeader h; InitEXRHeader(&h); EXRImage im; InitEXRImage(&im);
    std::vector<EXRChannelInfo> ci(nch); std::vector<int> types(nch, TINYEXR_PIXELTYPE_FLOAT); std::vector<float*> ptr(nch);
    for (int c=0;c<nch;++c){ memset(&ci[c],0,sizeof(EXRChannelInfo)); snprintf(ci[c].name, 255, "c%02d", c); ptr[c]=planes[c].data(); }
    h.num_channels=nch; h.channels=ci.data(); h.pixel_types=types.data(); h.requested_pixel_types=types.data(); h.compression_type=comp;
    im.num_channels=nch; im.images=(unsigned char**)ptr.data(); im.width=W; im.height=H;
    unsigned char* mem=nullptr; const char* err=nullptr;
    auto t=Clock::now(); size_t sz = SaveEXRImageToMemory(&im, &h, &mem, &err);
    printf("exr comp %d: %.1f ms %.1f MB\n", comp, Ms(t), sz/1e6); free(mem);
  }
}

// How a linear radiance image becomes 8-bit display pixels: an exposure in stops, then either
// plain sRGB encoding clipped at 1 (what -o's PNG has always been) or an AgX-style filmic curve
// that rolls highlights off to white and desaturates overexposed colours instead of clipping
// them per channel (docs/cli.md, "Tone mapping"). The live preview's frames and its PNG, and
// -o's PNG with --tonemap/--exposure, go through here.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "src/core/math.h"

namespace pt {

enum class ToneMapping { kClip, kAgx };

struct DisplaySettings {
  float exposure = 0.0f;  // stops: radiance x 2^exposure before the curve
  ToneMapping toneMapping = ToneMapping::kClip;
  bool IsDefault() const { return exposure == 0.0f && toneMapping == ToneMapping::kClip; }
};

const char* ToneMappingName(ToneMapping mapping);  // "clip", "agx"
// False for any other name.
bool ParseToneMapping(const std::string& name, ToneMapping* mapping);

// The AgX-style curve of one linear Rec.709 colour (already exposed): display-encoded values
// in [0, 1] (for an sRGB display). Mid grey 0.18 maps to 0.4614, sRGB's encoding of 0.18.
vec3 AgxDisplay(vec3 linear);

// 3 bytes a pixel (rgb holds 3 floats a pixel), rows as given.
std::vector<uint8_t> DisplayPixels(const std::vector<float>& rgb, const DisplaySettings& display);

}  // namespace pt

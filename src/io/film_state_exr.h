// A resumable render in an EXR: the image channels of an --hdr EXR plus the film's raw state
// (Welford mean and M2 exactly as the film holds them, the luminance statistics, per-pixel
// sample counts in the "samples" channel, feature sums) and a header attribute describing the
// render, so that a later run continues each pixel from its own count. Viewers show the image;
// the state lives in "state.*" channels.
#pragma once

#include <string>

#include "src/integrator/render_api.h"

namespace pt {

// The render's description, as the app writes it (a JSON text), in the header attribute
// kResumeAttribute.
inline constexpr const char* kResumeAttribute = "pathtracerResume";

// Writes image (with its variance, sample and feature channels) and the film state through a
// temporary file and a rename. doubleFilm: the film accumulates in double precision, so its
// mean and M2 are kept as the two 32-bit halves of each double (float films as floats; both
// exact). Throws ImageError.
void WriteResumableExr(const std::string& path, const FilmImage& image, const FilmState& film,
                       bool doubleFilm, const std::string& description);

struct ResumableExr {
  FilmState film;
  bool doubleFilm = false;
  std::string description;
};

// Reads what WriteResumableExr wrote. Throws ImageError when the file cannot be read, and when
// it is an EXR without a resumable state (an image only) or with a damaged one.
ResumableExr ReadResumableExr(const std::string& path);

}  // namespace pt

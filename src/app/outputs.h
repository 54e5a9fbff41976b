// The files a render writes: -o, --hdr (a resumable state when asked), --spp-map; checked for
// writability before anything is loaded.
#pragma once

#include <string>
#include <vector>

#include "src/app/cli.h"
#include "src/integrator/render_api.h"

namespace pt {

// Throws AppFailure (exit status 3) naming the first output that cannot be written.
void CheckOutputsWritable(const CliOptions& cli);

// A film state to keep in the --hdr EXR beside the image, so that --resume can continue it.
struct ResumableState {
  const FilmState* film = nullptr;
  bool doubleFilm = false;
  std::string description;  // the render's description (src/app/resume.h), as JSON text
};

// Writes -o (the denoised image when there is one), --hdr (the raw image, with the state when
// given and --hdr is an EXR) and --spp-map; returns the files written, in that order. Throws
// ImageError.
std::vector<std::string> WriteImages(const CliOptions& cli, const FilmImage& image,
                                     const ResumableState* state);

// The image at path in its extension's format; a PNG through the display settings (exposure
// and tone mapping; the default is plain sRGB clipping). Throws ImageError.
void WriteDisplayImage(const std::string& path, const FilmImage& image,
                       const DisplaySettings& display);

// The image -o shows at path: the denoised one when the film has it, else the image itself,
// through WriteDisplayImage. Throws ImageError.
void WriteShownImage(const std::string& path, const FilmImage& image,
                     const DisplaySettings& display);

// A checkpoint: the --hdr EXR with the state. Throws ImageError.
void WriteCheckpoint(const CliOptions& cli, const FilmImage& image, const ResumableState& state);

}  // namespace pt

#include "src/app/outputs.h"

#include <exception>
#include <future>

#include "src/app/app_failure.h"
#include "src/app/run.h"
#include "src/io/film_state_exr.h"
#include "src/io/image_io.h"
#include "src/io/tone_mapping.h"

namespace pt {

void CheckOutputsWritable(const CliOptions& cli) {
  for (const std::string* path :
       {&cli.outputPath, &cli.hdrPath, &cli.statsJsonPath, &cli.sppMapPath}) {
    std::string why;
    if (!path->empty() && !CheckWritable(*path, &why)) {
      throw AppFailure{kExitRuntimeFailure, "cannot write " + *path + ": " + why};
    }
  }
}

void WriteCheckpoint(const CliOptions& cli, const FilmImage& image, const ResumableState& state) {
  WriteResumableExr(cli.hdrPath, image, *state.film, state.doubleFilm, state.description);
}

void WriteDisplayImage(const std::string& path, const FilmImage& image,
                       const DisplaySettings& display) {
  ImageFormat format;
  if (display.IsDefault() || !ImageFormatFromPath(path, &format) || format != ImageFormat::kPng) {
    WriteImage(path, image, false);  // linear formats are never tone-mapped
    return;
  }
  WriteFileAtomic(path, EncodePng8(path, image.width, image.height,
                                   DisplayPixels(image.rgb, display)));
}

// The files are encoded and written at once, each on a thread of its own (the EXR's
// compression and the PNG's take about as long as each other at 1080p).
std::vector<std::string> WriteImages(const CliOptions& cli, const FilmImage& image,
                                     const ResumableState* state) {
  std::vector<std::string> written{cli.outputPath};
  std::vector<std::future<void>> others;
  if (!cli.hdrPath.empty()) {
    others.push_back(std::async(std::launch::async, [&] {
      if (state && IsExrPath(cli.hdrPath)) WriteCheckpoint(cli, image, *state);
      else WriteImage(cli.hdrPath, image, true);
    }));
    written.push_back(cli.hdrPath);
  }
  if (!cli.sppMapPath.empty()) {
    others.push_back(std::async(std::launch::async, [&] { WriteSppMap(cli.sppMapPath, image); }));
    written.push_back(cli.sppMapPath);
  }
  std::exception_ptr failure;
  try {
    WriteShownImage(cli.outputPath, image, cli.display);
  } catch (...) {
    failure = std::current_exception();
  }
  for (std::future<void>& f : others) {  // every write ends before the first error is thrown
    try {
      f.get();
    } catch (...) {
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  return written;
}

void WriteShownImage(const std::string& path, const FilmImage& image,
                     const DisplaySettings& display) {
  if (image.denoised.empty()) return WriteDisplayImage(path, image, display);
  FilmImage shown;  // --denoise: -o shows the denoised image
  shown.width = image.width;
  shown.height = image.height;
  shown.rgb = image.denoised;
  WriteDisplayImage(path, shown, display);
}

}  // namespace pt

#include "src/app/outputs.h"

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

std::vector<std::string> WriteImages(const CliOptions& cli, const FilmImage& image,
                                     const ResumableState* state) {
  std::vector<std::string> written;
  WriteDisplayImage(cli.outputPath, image, cli.display);
  written.push_back(cli.outputPath);
  if (!cli.hdrPath.empty()) {
    if (state && IsExrPath(cli.hdrPath)) WriteCheckpoint(cli, image, *state);
    else WriteImage(cli.hdrPath, image, true);
    written.push_back(cli.hdrPath);
  }
  if (!cli.sppMapPath.empty()) {
    WriteSppMap(cli.sppMapPath, image);
    written.push_back(cli.sppMapPath);
  }
  return written;
}

}  // namespace pt

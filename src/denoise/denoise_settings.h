// The denoiser's parameters (docs/denoise.md): Rousselle, Knaus and Zwicker's NL-means filter
// of the two half films (2012), each filtered with weights from the other, with the feature
// weights and the per-pixel choice among candidate filters of Rousselle, Manzi and Zwicker
// (2013).
#pragma once

namespace pt {

// One candidate filter's bandwidths: colour (NL-means k_c, in units of the noise's deviation)
// and features (k_f, in units of the feature's own gradient). Larger is looser.
struct DenoiseCandidate {
  float colorK = 0.45f;
  float featureK = 0.6f;
};

struct DenoiseSettings {
  int radius = 5;          // the search window: (2 radius + 1)^2 neighbours per pixel
  int patchRadius = 1;     // NL-means patches of (2 patchRadius + 1)^2 pixels
  // Candidates (1 to 3), from strict to loose; each pixel takes the one of least estimated
  // error summed over (2 selectRadius + 1)^2 pixels.
  int candidateCount = 3;
  DenoiseCandidate candidates[3] = {{0.35f, 0.5f}, {0.7f, 0.8f}, {1.2f, 1.2f}};
  int selectRadius = 3;
  // The smallest squared feature gradient a feature difference is measured against (tau).
  float featureTau = 1e-3f;
  // Fireflies scaled down to their neighbourhood's level before filtering (nlm_outliers.h,
  // Cycles' outlier detection): biased, and far less error where rare bright paths are.
  bool outliers = true;
  // The halves' variances scaled to how far the halves actually differ (nlm_variance.h),
  // which stratified samples (--sampler sobol) need: their sample variance overstates their
  // noise. The app turns it on for Sobol samples (src/app/denoise_step.cpp).
  bool calibrateVariance = false;
  // The emission camera rays see directly (FilmImage::emission) kept out of the filter and
  // added back: its only noise is the pixel footprint's, and an emissive texture's detail is
  // in no feature. Where that footprint noise is large (independent samples; a bright
  // light's edge even under Sobol samples) filtering it with the rest measured better, so it
  // is off unless asked for (--denoise-emission keep; docs/denoise.md).
  bool keepSeenEmission = false;
};

// The settings a denoiser accepts; returns an empty string, or what is wrong.
inline const char* DenoiseSettingsProblem(const DenoiseSettings& s) {
  if (s.radius < 1 || s.radius > 20) return "radius must be 1..20";
  if (s.patchRadius < 0 || s.patchRadius > 3) return "patch radius must be 0..3";
  if (s.candidateCount < 1 || s.candidateCount > 3) return "1 to 3 candidate filters";
  if (s.selectRadius < 0 || s.selectRadius > 8) return "selection radius must be 0..8";
  for (int k = 0; k < s.candidateCount; ++k) {
    if (!(s.candidates[k].colorK > 0.0f) || !(s.candidates[k].featureK > 0.0f))
      return "bandwidths must be positive";
  }
  if (!(s.featureTau > 0.0f)) return "tau must be positive";
  return "";
}

}  // namespace pt

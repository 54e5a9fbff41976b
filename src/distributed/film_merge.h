// Combining films of disjoint sample sets: Chan, Golub and LeVeque's parallel form of
// Welford's update (1979), per pixel and channel, in double precision:
//   n = na + nb,  d = mean_b - mean_a,  mean = mean_a + d * nb / n,
//   M2 = M2_a + M2_b + d^2 * na * nb / n,
// the luminance statistics adaptive sampling reads likewise, counts, feature sums and the
// even-sample half film added.
// A side with no samples leaves the other exactly as it was, so an empty film is an identity.
#pragma once

#include "src/integrator/render_api.h"

namespace pt {

// into := into (+) from, `into` holding the lower samples. Throws std::invalid_argument when
// the films differ in size or feature channels. Pixels are split over `threads` threads;
// every pixel's arithmetic is the same whatever the split.
void MergeFilmInto(FilmState& into, const FilmState& from, int threads = 1);

// A film of the given size with no samples (feature and half-film channels when asked).
FilmState EmptyFilm(uint32_t width, uint32_t height, bool features, bool halves = false);

}  // namespace pt

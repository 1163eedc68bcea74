// Photographs: an object lit from one side, whose shaded parts come close to the backdrop's
// colour (a white plaster figure on black cloth with its crevices in shadow). A threshold
// alone cuts the shadows out of some views and not of others; here the threshold only
// picks the seeds, and the object grows from them through what is lighter than the
// backdrop and has the object's colour.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "io/image_io.h"

namespace cm {

/// What segment_photo found.
struct PhotoCut {
    std::vector<char> object;             ///< w*h, row-major: 1 = object
    double weak_threshold = 0;            ///< distance from the border's field a grown pixel needs
    std::size_t seeds = 0, grown = 0;     ///< pixels beyond the threshold; pixels the cut added to them
    std::size_t demoted = 0;              ///< pixels beyond the threshold of a backdrop's colour (step 3)
    int holes_filled = 0, holes_kept = 0; ///< enclosed regions (see segment_photo)
};

/// @brief Segments a photograph: `dist` is each pixel's distance to its backdrop (in units
/// where `t` is the threshold), `source` which backdrop that is (0 the border's field, k the
/// k-th further border colour where it reaches, below `backgrounds`), `noise` the border's
/// spread around the field.
/// 1. Seeds: pixels at least `t` from their backdrop. Growth starts from seed components of
///    at least 5 % of the largest (a speck of grain does not grow).
/// 2. Weak threshold, per backdrop: three times the 90th percentile of its border pixels'
///    distances, kept within [t / 4, t / 2]. The region growth may reach: pixels at least
///    that far from their backdrop, 8-connected to the growing seeds through such pixels.
/// 3. Colour models in chromaticity (R and G over R + G + B, which shading leaves alone),
///    each a median with a MAD spread: the object's from the seeds' interior (R + G + B at
///    least 50 x the noise), each backdrop's from its pixels away from the seeds (beyond 3 %
///    of the larger side), the brightest of them when few reach 50 x the noise (at least the
///    90th percentile's R + G + B, and 10 x the noise). In seed components reaching the
///    image border, seeds whose colour evidence (step 4) is -2 or less, clearly a backdrop's
///    (a lit fold of a dark cloth, a wall beside it), are no longer seeds: all of a component
///    whose median evidence is -1 or less, else those not beside a seed of the object's
///    colour. The cut decides them.
/// 4. The region's weak pixels are labelled by a minimum cut (MinCut) of an energy with a
///    colour term per pixel (squared chromaticity distances to the two models over twice
///    their common variance, widened by the noise of a ratio of small numbers; within +-4;
///    0 for a pixel too dark to tell) and a cost of 4 per pair of 8-neighbours labelled
///    apart (over their distance); seeds are object, pixels outside the region backdrop.
///    Then each backdrop's model is fitted again to the weak pixels the cut gave it (the
///    backdrop at their brightness, next to the object) and the cut made again.
/// 5. What the border reaches (4-connected) through the rest, with breaks narrower than
///    `close_gaps` px bridged (0: none; see close_ink), is background. Enclosed regions
///    follow `holes`: fill makes them object, keep keeps them open, and auto keeps open the
///    see-through gaps: regions of at least 3 % of the object's area whose mean colour
///    evidence is -1 or less where at least a quarter of them is bright enough to tell, else
///    at least 60 % as dark as a backdrop, with no evidence for the object; the rest (a
///    shadow the object casts on itself, small beside it) becomes object.
PhotoCut segment_photo(const Image& img, const std::vector<double>& dist, const std::vector<unsigned char>& source,
                       int backgrounds, double t, double noise, const std::string& holes, double close_gaps);

} // namespace cm

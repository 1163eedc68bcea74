// From a drawing to a silhouette (coverage in [0,1], anti-aliased edges kept).
#pragma once
#include <string>
#include <utility>
#include <vector>

#include "core/views.h"
#include "io/image_io.h"
#include "line_art.h"
#include "silhouette_holes.h"

namespace cm {

struct SilhouetteOptions {
    /// auto | alpha | a colour ("#rrggbb", "r,g,b" in 0-255, "white", "black", "grey").
    std::string background = "auto";
    /// Colour distance (0-1, RMS over R, G, B) from the background that makes a pixel object;
    /// < 0: from the spread of the image border.
    double threshold = -1;
    /// auto: drop specks and separate marks much smaller than the object; largest; all.
    std::string keep = "auto";
    /// Regions enclosed by the object that look like the background: auto (holes by evidence:
    /// the background seen through a filled drawing; none in line art), fill (always object),
    /// keep (every region of a filled drawing, the nested regions of line art).
    std::string holes = "auto";
    /// Breaks in the ink up to this many pixels wide are closed before the background is
    /// flooded from the border; < 0: 0.4 % of the image's larger side, at least 3 px; 0: off.
    double close_gaps = -1;
    /// auto: a soft ground shadow under the object is background; keep: it stays object.
    std::string shadow = "auto";
    /// on: segment as a photograph (seeds beyond the threshold grown through the object's
    /// shaded parts, see segment_photo); off: as a drawing; auto: as a drawing (views.load
    /// turns calibrated views to on).
    std::string photo = "auto";
    /// Analyse a drawing only in the window around its ink (its box grown by more than any
    /// step reaches), when that is at most half the image; false: always the whole image.
    /// The answers are the same (a test holds them side by side).
    bool window = true;
    /// Line art: the enclosed regions holding these image points (x, y) are holes whatever
    /// the drawing alone says (views.load: the openings the opposite view confirmed).
    std::vector<std::pair<int, int>> open_at;
};

struct SilhouetteResult {
    Coverage coverage;    ///< over the image, row 0 at the top
    std::string method;   ///< "alpha" or "background"
    double threshold = 0; ///< the colour distance used (background method)
    double noise = 0;     ///< spread of the border around the background model
    int components_kept = 0, components_dropped = 0;
    int holes_kept = 0, regions_filled = 0; ///< enclosed background-like regions
    double close_gaps = 0;                  ///< the gap closed (pixels), background method
    int border_colours = 0;                 ///< background colours found along the border
    std::size_t shadow_removed = 0;         ///< ground-shadow pixels made background
    std::size_t spurs_removed = 0;          ///< overshooting-stroke pixels made background
    std::size_t slits_opened = 0;           ///< line art: pixels of slits between parts kept open
    bool photo = false;                     ///< segmented as a photograph
    double weak_threshold = 0;              ///< photograph: the colour distance growth needs;
                                            ///< drawing: the one faint ink along clear ink needs
    std::size_t weak_ink = 0;               ///< drawing: faint pixels read as ink (raise_weak_ink)
    std::size_t grown = 0;                  ///< photograph: pixels joined to the seeds by growth
    std::size_t analysed_pixels = 0;        ///< pixels the analysis went over (the window, or all)
    std::vector<EnclosedRegion> regions;    ///< the enclosed blank regions, judged (drawings)
    StrokeCentre stroke;                    ///< line art: its outline moved to the strokes' centre
};

/// @brief Extracts the silhouette of the object in a drawing.
/// A meaningful alpha channel (some pixels transparent, some opaque) is the coverage.
/// Otherwise the background is modelled from the image border (a smooth colour field that
/// follows vignetting, with a spread that follows grain and compression noise) and the
/// object is everything not connected to it. Edge pixels keep fractional coverage.
/// @throw cm::Error for an unusable option (a bad colour name).
SilhouetteResult extract_silhouette(const Image& img, const ImageInfo& info, const SilhouetteOptions& opt);

} // namespace cm

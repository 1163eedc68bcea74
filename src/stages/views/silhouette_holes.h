// Holes by evidence: which blank regions a drawing encloses are openings through the object,
// and which are parts of it drawn in the paper's colour (white eyes, teeth, a stripe), surface
// detail of line art, or paper showing between hatch strokes.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace cm {

/// Enclosed regions of a drawing under this many pixels are gaps between strokes, never
/// holes (unless every region is kept, `holes: keep`); pockets.h fills the partly covered
/// ones.
inline constexpr std::size_t kStrokeGapArea = 9;

/// One blank region a drawing encloses, and what was made of it.
struct EnclosedRegion {
    std::size_t area = 0;              ///< pixels
    int x = 0, y = 0;                  ///< its centre (mean pixel), in the analysed image
    bool hole = false;                 ///< opened: background
    bool candidate = false;            ///< line art: a hole by nesting, opened only on further evidence
    bool between_parts = false;        ///< a candidate bounded by the outlines of parts (see nested_holes)
    bool witness = false;              ///< line art: the inside, of an opening's size (see judge_line_regions)
    std::string why;                   ///< what decided it, in a few words
    std::vector<std::uint32_t> pixels; ///< candidates: the region's pixels (row-major image indices)
};

/// What the regions are judged on, all w x h, row-major.
struct RegionEvidence {
    const std::vector<int>* region = nullptr;        ///< blank region label, -1 elsewhere
    int count = 0;                                   ///< number of regions
    const std::vector<std::size_t>* sizes = nullptr; ///< pixels per region
    const std::vector<char>* outside = nullptr;      ///< what the border flood reached
    const std::vector<double>* distance = nullptr;   ///< colour distance to the background
    const std::vector<float>* luminance = nullptr;   ///< 0 black, 1 white
    const std::vector<char>* ink = nullptr;          ///< black or grey ink (dark, not coloured)
    double threshold = 0;                            ///< distance that makes a pixel object
    int w = 0, h = 0;
};

/// @brief The width in pixels of the ink outline drawn around the object: the median run of
/// dark pixels (under half the paper's luminance) met going in from the outside along rows
/// and columns; 0 when fewer than half the crossings meet ink (a flat fill, no outline).
double outline_width(const RegionEvidence& e);

/// @brief The deepest pixel of each region: its chessboard distance to the nearest pixel
/// outside the region (1 on its rim). A region whose deepest pixel is shallow is a sliver.
std::vector<int> region_depths(const RegionEvidence& e);

/// @brief The enclosed regions of a filled drawing (more ink than blank). A region is a hole
/// when it shows the outside background through the fill; it is a part when
/// - it is a sliver (no pixel deeper than max(2, outline width)) in a hatched drawing (20
///   slivers or more): paper between strokes. Without hatching a sliver is a narrow gap
///   between parts (an ear beside a head), a hole;
/// - it comes within the outline's width of the outside: its own outline is the body's
///   (an eye on the edge of a head, a stripe across the body). Without an ink outline (a
///   flat fill, a mask) at least 0.15 of its rim must lie there: a gap between an arm and
///   the body, shut by a hand touching the hip, is a hole;
/// - most of its rim is ink joined to the ink around the body (a shirt between drawn lapels);
/// - it is under 0.25 % of the drawing's area (a highlight in a pupil): no opening that
///   small would survive the hull's resolution;
/// - it holds a mark of its own (a pupil): an opening shows nothing floating inside it;
/// - it is tinted: its mean colour distance is over half the threshold (a pale grey eye).
/// Regions under `min_area` pixels are gaps between strokes (parts).
std::vector<EnclosedRegion> judge_filled_regions(const RegionEvidence& e, std::size_t min_area);

/// @brief The enclosed regions of a line drawing. `nested` says per region what nested_holes
/// found: the regions behind an even number of strokes and the gaps between parts, at
/// least `min_area` pixels (and, unless `open_candidates`, 0.25 % of the drawing, as a
/// filled drawing's openings) and not slivers, are candidates; a candidate is a hole only when
/// `open_candidates` (holes: keep) or when the opposite view shows it too (see
/// open_confirmed_holes); every other region is the object's inside or surface detail. A
/// region of the inside that would pass every test but nesting is a witness: it cannot open
/// itself, but it confirms a candidate of the opposite view drawn at the same place.
std::vector<EnclosedRegion> judge_line_regions(const RegionEvidence& e, const std::vector<char>& nested,
                                               std::size_t min_area, bool open_candidates);

/// Marks as holes the regions of `lab` (w x h, at (ox, oy) in the image) that hold the image
/// points `at`: the openings the opposite view confirmed (see open_confirmed_holes).
void open_regions_at(std::vector<EnclosedRegion>& regions, const std::vector<int>& lab, int w, int h, int ox, int oy,
                     const std::vector<std::pair<int, int>>& at);

/// Every region judged alike (holes: keep or fill), `why` the reason given.
std::vector<EnclosedRegion> judge_all_regions(const RegionEvidence& e, bool hole, const std::string& why);

/// A one-line account of the holes: each opened region with its area and centre, and how
/// many of at least 9 px were kept as parts and why; empty when there is nothing to say.
std::string describe_regions(const std::vector<EnclosedRegion>& regions);

} // namespace cm

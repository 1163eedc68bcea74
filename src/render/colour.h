// Colour arithmetic shared by texturing and its evaluation: sRGB transfer, CIELAB and
// the CIE76 colour difference (delta E: about 2.3 is a just noticeable difference).
#pragma once
#include <array>

namespace cm {

float srgb_to_linear(float c); ///< sRGB-encoded [0,1] to linear
float linear_to_srgb(float c); ///< linear [0,1] to sRGB-encoded
/// CIELAB (D65) of an sRGB-encoded colour.
std::array<double, 3> srgb_to_lab(const std::array<float, 3>& srgb);
/// sRGB-encoded colour (clamped to [0,1]) of a CIELAB (D65) colour.
std::array<float, 3> lab_to_srgb(const std::array<double, 3>& lab);
/// CIE76 delta E between two sRGB-encoded colours.
double delta_e76(const std::array<float, 3>& a, const std::array<float, 3>& b);

} // namespace cm

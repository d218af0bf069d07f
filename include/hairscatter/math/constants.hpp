// hairscatter — mathematical constants as variable templates, usable on host and device.
#pragma once

namespace hairscatter {

template <typename T> inline constexpr T kPi = T(3.14159265358979323846264338327950288);
template <typename T> inline constexpr T kTwoPi = T(6.28318530717958647692528676655900577);
template <typename T> inline constexpr T kHalfPi = T(1.57079632679489661923132169163975144);
template <typename T> inline constexpr T kQuarterPi = T(0.785398163397448309615660845819875721);
template <typename T> inline constexpr T kInvPi = T(0.318309886183790671537767526745028724);
template <typename T> inline constexpr T kInvTwoPi = T(0.159154943091895335768883763372514362);
template <typename T> inline constexpr T kSqrtPiOver8 = T(0.626657068657750125603941321203029170);
template <typename T> inline constexpr T kInvSqrtTwoPi = T(0.398942280401432677939946059934381868);
template <typename T> inline constexpr T kLn2 = T(0.693147180559945309417232121458176568);

// Machine constants as plain variable templates: std::numeric_limits' members are host
// functions as far as a CUDA compiler without --expt-relaxed-constexpr is concerned.
template <typename T> inline constexpr T kEpsilon = T(0);
template <> inline constexpr float kEpsilon<float> = 1.1920928955078125e-07f;
template <> inline constexpr double kEpsilon<double> = 2.220446049250313080847e-16;
template <typename T> inline constexpr T kMinNormal = T(0);
template <> inline constexpr float kMinNormal<float> = 1.17549435082228750797e-38f;
template <> inline constexpr double kMinNormal<double> = 2.2250738585072013830902e-308;

// The colour channels a model keeps per lobe in its hot path: RGB, padded to four so
// that each lobe's channels are one whole vector (a loop over three is left scalar, or
// split into a vector and a remainder); the fourth channel is padding (σa = 0, gain 1)
// and never read as colour.
inline constexpr int kChannelLanes = 4;
static_assert(kChannelLanes >= 3, "RGB at least");

// Degrees to radians, for parameters given in degrees (cuticle tilt is usually 2°).
template <typename T> constexpr T radians(T degrees) { return degrees * (kPi<T> / T(180)); }

}  // namespace hairscatter

// glint — blackbody emission: the colour and strength of a body's thermal radiation at a
// temperature, for fire (VDB temperature grids, materials/vdb_volume.h).
//
// Units and normalisation (the same luminance as Cycles' Principled Volume at Blackbody
// Intensity 1; below about 1,900 K Cycles 3.4 keeps the negative components this clamps):
//   blackbodyEmission(T) = 1e-6 sigma T^4 / pi x rgb(T)
// sigma T^4 / pi is the radiance of a black body (W m^-2 sr^-1, Stefan–Boltzmann: Planck's
// law integrated over all wavelengths); the 1e-6 maps it to scene units so that a flame of
// 1,500 K emits about 0.09 per unit length. rgb(T) is the colour of Planck's spectrum: the
// spectrum integrated against the CIE 1931 2-degree observer (Wyman, Sloan and Shirley's
// multi-lobe fit, JCGT 2013) into XYZ, converted to linear Rec.709 (glint's working space),
// negative components clamped to 0 (below about 1,900 K the spectrum lies outside the
// gamut), and scaled to luminance Y = 1, so the luminance of the whole is 1e-6 sigma T^4 / pi.
#pragma once

#include "geometry/math.h"

namespace glint {

// The Stefan–Boltzmann constant (W m^-2 K^-4).
inline constexpr double kStefanBoltzmann = 5.670374419e-8;

// Planck's law: the spectral radiance of a black body at `kelvin` (W sr^-1 m^-3) at the
// wavelength `nm` nanometres.
double planck(double nm, double kelvin);

// The CIE 1931 colour matching functions at `nm` (the multi-lobe fit).
Vec3f cieXyz(float nm);

// Linear Rec.709 from CIE XYZ (D65 white).
Rgb rec709FromXyz(Vec3f xyz);

// The colour of a black body at `kelvin` with luminance 1 (see above); temperatures below
// 500 K take the colour of 500 K, above 40,000 K that of 40,000 K. Tabulated at first use.
Rgb blackbodyColor(float kelvin);

// Radiance per unit length of blackbody emission at `kelvin` (>= 0; 0 gives 0), as above.
Rgb blackbodyEmission(float kelvin);

}  // namespace glint

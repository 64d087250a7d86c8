// glint — the physics of the layers glTF's material extensions put on top of the
// metallic-roughness base (pbr.h): Charlie sheen (KHR_materials_sheen), thin-film interference
// (KHR_materials_iridescence), the spectral index of refraction (KHR_materials_dispersion).
// Free functions of plain numbers, so that each is tested against its closed form alone
// (tests/materials/layers_test.cpp) before PbrBxdf combines them.
#pragma once

#include "geometry/math.h"

namespace glint {

// ---- Sheen: the "Charlie" microfiber distribution (Estevez and Kulla 2017) ------------------
// alpha = sheenRoughness^2, clamped below at kMinSheenAlpha (the distribution degenerates at 0).
inline constexpr float kMinSheenAlpha = 1e-3f;

// D(h) = (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), normalised so that the integral of
// D cos(theta_h) over the hemisphere is 1; cosH = cos(theta_h).
float sheenD(float cosH, float alpha);
// The sheen BRDF for a white sheen colour: D V, with Estevez and Kulla's fitted masking
// term V = 1 / ((1 + Lambda(wo) + Lambda(wi)) 4 cos(wo) cos(wi)) (as the Khronos sample viewer
// uses it). Zero below the surface.
float sheenBrdf(float cosO, float cosI, float cosH, float alpha);
// The directional albedo E(cos(wo)) of sheenBrdf: the fraction of light a white sheen reflects
// (integrated numerically once per process into a 32 x 32 table over sqrt(cos(wo)), dense
// near the horizon where it changes fastest, and sheenRoughness; bilinear in between). The base
// below a sheen layer gets 1 - max(sheenColor) E of the light (KHR_materials_sheen's albedo
// scaling).
float sheenAlbedo(float cosO, float sheenRoughness);

// ---- Thin-film interference (Airy summation) ----------------------------------------------
// The reflectance of a film of index filmIor and thickness `thicknessNm`, lying on a substrate
// of index substrateIor, seen from air at incidence cosine cosI, for light of wavelength
// lambdaNm, averaged over the two polarisations; the film and substrate are dielectrics, so
// the amplitude coefficients are real. A substrate index below the film's can reflect totally:
// then the result is 1. Thickness 0 gives the bare substrate's Fresnel reflectance.
float thinFilmReflectance(float cosI, float filmIor, float substrateIor, float thicknessNm,
                          float lambdaNm);
// The RGB reflectance of such a film: each channel the mean over three wavelengths of its band
// (red 580-680 nm, green 500-580, blue 420-500), per channel substrate index (a metal's from
// its base colour's F0, as the Khronos viewer does).
Rgb thinFilmFresnel(float cosI, float filmIor, Rgb substrateIor, float thicknessNm);
// The index of refraction whose normal-incidence Fresnel reflectance is f0 (in [0, 1)).
float iorFromF0(float f0);

// ---- Dispersion ------------------------------------------------------------------------------
// The wavelengths glint's three colour channels stand for when a refraction splits them
// (KHR_materials_dispersion): red, green, blue.
inline constexpr float kChannelWavelengthNm[3] = {630, 532, 465};
// The index at lambdaNm for a material of index `ior` (at the Fraunhofer d line, 587.6 nm) and
// glTF's `dispersion` = 20 / Abbe number: Cauchy's two-term fit through n_d with Abbe number V,
//   n(lambda) = ior + (ior - 1) / V (523655 / lambda^2 - 1.5168),
// the formula of KHR_materials_dispersion. Never below 1.
float dispersedIor(float ior, float dispersion, float lambdaNm);

}  // namespace glint

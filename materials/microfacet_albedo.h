// glint — the directional albedos of GGX reflection, tabulated for energy compensation.
//
// A single-scattering microfacet lobe (microfacet.h) loses the light that bounces between
// microfacets more than once: a white rough metal reflects only 31% at roughness 1 and normal
// incidence. Kulla and Conty ("Revisiting Physically Based Shading at Imageworks", SIGGRAPH
// 2017 course) add it back as a second, diffuse-like lobe built from the first one's
// directional albedo E(mu); and the layer below a specular interface (glTF's diffuse) gets
// what the interface leaves, 1 - E_F(mu), in the reciprocal "albedo scaling" form
//   f_below(wo, wi) = f(wo, wi) (1 - E_F(mu_o)) (1 - E_F(mu_i)) / (1 - E_F,avg),
// whose albedo is exactly (1 - E_F(mu_o)) times f's (for a Lambertian f). PbrBxdf (bxdfs.h)
// uses both; these are its tables.
//
// E is tabulated over sqrt(cos(wo)) (dense near the horizon, where E changes fastest) x
// perceptual roughness x sqrt(F0) of the index, 32 x 32 x 16 entries, trilinear in between.
// The table is generated offline (tools/make_albedo_table.cpp: a 1024 x 1024 quadrature per
// entry, a minute of work that a renderer should not repeat at every start) into
// microfacet_albedo_table.inc. The averages E_avg = 2 int E(mu) mu dmu are computed at first
// use from the interpolated E itself, so that the albedo scaling above conserves energy to the
// table's own accuracy.
#pragma once

namespace glint {

// The table's axes: sqrt(cos(wo)), perceptual roughness, sqrt(F0) (its last slice F = 1).
inline constexpr int kAlbedoTableMu = 32, kAlbedoTableRoughness = 32, kAlbedoTableF0 = 16;

// The albedo of GGX reflection (height-correlated Smith masking) with Fresnel factor 1, at
// view cosine cosO and perceptual roughness (alpha = roughness^2, at least 1e-4).
float ggxAlbedo(float cosO, float roughness);
// Its cosine-weighted hemispherical average.
float ggxAverageAlbedo(float roughness);

// The albedo of GGX reflection weighted by the exact dielectric Fresnel reflectance for the
// relative index eta (eta < 1, seen from the denser side, is looked up as 1 / eta: the
// albedo scaling of an opaque layer only ever sees eta >= 1), and its average.
float ggxDielectricAlbedo(float cosO, float roughness, float eta);
float ggxDielectricAverageAlbedo(float roughness, float eta);

// Sampling Kulla and Conty's multiple-scattering lobe, f_ms(wo, wi) proportional to
// 1 - E(cos wi): cos wi drawn with density proportional to (1 - E(mu)) mu (over 64 bins of
// sqrt(mu) per roughness row of the table, each bin's share exact and mu-shaped inside it;
// neighbouring rows mixed by their share of the lobe), the azimuth uniform. A cosine-sampled
// lobe weighs (1 - E(mu)) / (1 - E_avg) per sample, 9 and more for a smooth metal seen and lit
// at grazing angles; sampled this way the weight stays near the lobe's albedo whatever the
// direction. Returns cos wi; *pdf is the density per unit solid angle.
float sampleMultipleScatteringCos(float roughness, float u, float* pdf);
// That density at cos wi = mu (0 below the horizon).
float multipleScatteringPdf(float mu, float roughness);

// The cosine-weighted hemispherical average of the exact dielectric Fresnel reflectance,
// 2 int F(mu, eta) mu dmu (a 256-entry table over sqrt(F0)): the smooth interface's E_F,avg.
float dielectricFresnelAverage(float eta);

}  // namespace glint

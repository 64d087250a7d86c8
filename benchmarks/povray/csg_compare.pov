// POV-Ray 3.7 half of the glint / POV-Ray comparison (issue 27); csg_compare.json is the same
// scene for glint. The course competition's kind of scene: a checker floor, a box minus four
// spheres, the intersection of three cylinders, a cone united with a sphere, a marble sphere,
// a glass sphere, one point light; 800x600 (the size comes from the command line, +W800 +H600).
//
// POV-Ray is left-handed (x right, y up, z into the screen); glint (glTF) is right-handed
// (x right, y up, z towards the viewer). The JSON is this scene mirrored in z: a POV point
// <x, y, z> is glint's [x, y, -z], and `rotate y*a` (or x*a) here is a rotation by -a degrees
// about +Y (+X) there; rotations about z keep their sign.
//
// Matching glint's units, with I the JSON's point-light intensity (candela) and d the distance:
//   - glint's Lambert: radiance = diffuse / pi * I / d^2 * cos. POV-Ray's diffuse term is
//     pigment * diffuse * light colour * attenuation * cos, with attenuation
//     2 / (1 + (d / fade_distance)^2) for fade_power 2, about 2 * fade_distance^2 / d^2 here
//     (d >= 8 against fade_distance 0.1: 1.6e-4 relative). So the light colour is
//     I / (2 pi fade_distance^2) and every finish has ambient 0, diffuse 1.
//   - glint's Phong: ks * (n + 2) / (2 pi) * cos^n(alpha) * I / d^2 * cos(theta_i).
//     POV-Ray's phong highlight is phong * cos^n(alpha) * light colour * attenuation, with no
//     cos(theta_i): `phong ks * (n + 2) / 2` matches the peak where the light is overhead.
//   - glint's glass (ior 1.5): Fresnel-weighted reflection and refraction, both followed, and
//     shadows filtered through it; POV-Ray: filter 1, reflection {0, 1 fresnel}, conserve_energy.
//   - glint's marble (0.5 + 0.5 sin(4 x + 6 turbulence)) is not POV-Ray's marble: same
//     colours, a sine wave of the same period along x, turbulence chosen to look alike; the
//     veins are not the same veins.

#version 3.7;

global_settings {
  assumed_gamma 1.0       // linear light throughout; +FE (OpenEXR) output stays linear
  max_trace_level 8       // glint's integrator.max_depth
}

#declare FadeDistance = 0.1;
#declare LightIntensity = 300;   // the JSON's "intensity" (candela)

// glint: yfov_degrees 40 at 4:3. POV-Ray's `angle` is the horizontal field of view.
camera {
  location <0, 3.6, -10.5>
  look_at <0, 1.0, 0>
  right x * 4/3
  up y
  angle 2 * degrees(atan(4/3 * tan(radians(40 / 2))))
}

background { color rgb <0.45, 0.55, 0.7> }

light_source {
  <-5, 9, -6>
  color rgb LightIntensity / (2 * pi * FadeDistance * FadeDistance)
  fade_distance FadeDistance
  fade_power 2
}

#default { finish { ambient 0 diffuse 1 } }

#macro Lambert(C)
  texture { pigment { color rgb C } finish { ambient 0 diffuse 1 } }
#end
#macro Phong(C, Ks, N)
  texture { pigment { color rgb C } finish { ambient 0 diffuse 1 phong Ks * (N + 2) / 2 phong_size N } }
#end

// The floor: 1-unit checks (3D cubes, as glint's solid checker), the pattern moved half a unit
// in y so the plane y = 0 is not on a cube face.
plane {
  y, 0
  texture {
    pigment { checker color rgb <0.8, 0.78, 0.72> color rgb <0.12, 0.14, 0.2> translate <0, 0.5, 0> }
    finish { ambient 0 diffuse 1 }
  }
}

// A box minus four spheres, one on each upper corner.
difference {
  box { <-0.9, 0, -0.9>, <0.9, 1.8, 0.9> }
  sphere { < 0.9, 1.8,  0.9>, 0.6 Lambert(<0.85, 0.7, 0.15>) }
  sphere { <-0.9, 1.8,  0.9>, 0.6 Lambert(<0.85, 0.7, 0.15>) }
  sphere { < 0.9, 1.8, -0.9>, 0.6 Lambert(<0.85, 0.7, 0.15>) }
  sphere { <-0.9, 1.8, -0.9>, 0.6 Lambert(<0.85, 0.7, 0.15>) }
  Phong(<0.7, 0.12, 0.1>, 0.2, 40)
  rotate y * 25
  translate <-3.3, 0, 0.8>
}

// The intersection of three cylinders (a tricylinder), tilted.
intersection {
  cylinder { <-0.8, 0, 0>, <0.8, 0, 0>, 0.75 }
  cylinder { <0, -0.8, 0>, <0, 0.8, 0>, 0.75 }
  cylinder { <0, 0, -0.8>, <0, 0, 0.8>, 0.75 }
  Phong(<0.15, 0.55, 0.2>, 0.2, 60)
  rotate x * 30
  rotate y * 35
  translate <-1.1, 0.95, 2.6>
}

// A cone united with a sphere at its tip.
union {
  cone { <0, 0, 0>, 0.75, <0, 1.7, 0>, 0 Lambert(<0.15, 0.25, 0.7>) }
  sphere { <0, 1.6, 0>, 0.45 Phong(<0.72, 0.72, 0.7>, 0.25, 80) }
  translate <1.3, 0, 2.8>
}

// The marble sphere.
sphere {
  <0, 0, 0>, 1
  texture {
    pigment {
      marble
      sine_wave
      turbulence 0.9
      octaves 5
      color_map { [0 color rgb <0.85, 0.83, 0.78>] [1 color rgb <0.25, 0.2, 0.35>] }
      scale 2 * pi / 4   // glint's frequency 4: a period of 2 pi / 4 along x
    }
    finish { ambient 0 diffuse 1 phong 0.15 * (50 + 2) / 2 phong_size 50 }
  }
  translate <3.3, 1, 0.4>
}

// The glass sphere, in front.
sphere {
  <0, 0, 0>, 0.9
  material {
    texture {
      pigment { color rgbf <1, 1, 1, 1> }
      finish { ambient 0 diffuse 0 reflection { 0, 1 fresnel on } conserve_energy }
    }
    interior { ior 1.5 }
  }
  translate <0.2, 0.9, -1.3>
}

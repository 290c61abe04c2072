// The classic Whitted scene for POV-Ray 3.7: a checkered floor, a Phong sphere, a mirror
// sphere and a glass sphere under two point lights. benches/povray/whitted.toml is the
// same scene for Prism, and benches/povray.sh times the two against each other.
//
// POV-Ray is left-handed and Prism right-handed: every z here is Prism's negated, which
// keeps +x on the right of the image. Colours are linear (assumed_gamma 1) and written
// with File_Gamma=sRGB, as Prism develops its radiance.
//
//   povray +Iwhitted.pov +Owhitted.png +W1280 +H720 -D -GA File_Gamma=sRGB +WT2
//
// Anti-aliasing 3 is `+A0.0 +AM1 +R3 -J`: method 1 supersamples a pixel whose colour
// differs from its left or upper neighbour by at least the threshold, so a threshold of
// 0 supersamples every pixel, each with a regular 3x3 grid (-J: no jitter, as Prism's
// grid). Method 1 keeps the pixel's first centre ray in the mean (and traces the row
// above and the column left of each tile once more), so POV-Ray traces about 10 camera
// rays a pixel where Prism's --aa 3 traces 9; method 2 (adaptive, corners shared
// between pixels) cannot be made to trace a fixed 9.

#version 3.7;

global_settings {
  assumed_gamma 1.0
  // Level 1 is the camera ray: 6 allows five bounces, Prism's max_depth = 5.
  max_trace_level 6
  adc_bailout 1/255
  ambient_light rgb 0.1
}

camera {
  perspective
  location <0, 1.5, -7>
  look_at <0, 1, 0>
  right x * image_width / image_height
  angle 55  // horizontal, as Prism's fov
}

background { rgb <0.4, 0.6, 0.9> }

light_source { <-5, 8, -6> color rgb <0.8, 0.78, 0.75> }
light_source { <6, 5, -3> color rgb <0.45, 0.5, 0.6> }

// Prism's ambient term for a checker is its mean colour, POV-Ray's each cell's own: the
// floor takes none in either, so the two agree.
plane {
  y, 0
  pigment { checker rgb <0.8, 0.8, 0.8>, rgb <0.05, 0.05, 0.05> }
  finish { ambient 0 diffuse 0.9 }
}

sphere {
  <-2.3, 1, 0.5>, 1
  pigment { rgb <0.7, 0.12, 0.08> }
  finish { ambient 1 diffuse 0.8 phong 0.6 phong_size 60 }
}

sphere {
  <0.2, 1.2, 2.6>, 1.2
  pigment { rgb 0 }
  finish { ambient 0 diffuse 0 phong 0.6 phong_size 200 reflection 0.9 }
}

// Filter 1 with colour 0.9: the refracted ray and each shadow-ray crossing keep 0.9;
// with fresnel reflection and conserve_energy the surface reflects F and transmits
// 0.9 (1 - F), Prism's `transmission = 0.9, fresnel = true`.
sphere {
  <1.9, 1, -0.8>, 1
  pigment { rgbf <0.9, 0.9, 0.9, 1> }
  finish {
    ambient 0 diffuse 0 phong 0.6 phong_size 200
    reflection { 0, 1 fresnel on }
    conserve_energy
  }
  interior { ior 1.5 }
}

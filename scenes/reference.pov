// The reference scene (scenes/reference.yml) for POV-Ray 3.7, written by hand: the
// anchor of the report's "Step by step" (rtc bench --sections ladder). Every number is the
// YAML scene's; the book's lighting is Phong's, as POV-Ray's classic finish:
//   ambient * colour + diffuse * colour * (N.L) + phong * light * (R.V)^phong_size
// Transforms are written as matrices where the book's order matters (the back wall).
//
// Where the two pictures may differ (the report measures how much, and shows where):
//   - the glass sphere: the book adds its surface colour (diffuse 0.2), the Schlick-weighted
//     reflection and the refraction; POV-Ray weights a transparent surface's own colour by
//     its opacity and uses exact Fresnel reflection;
//   - POV-Ray's +WxH sets the size; the camera's field of view stays (as rtc's --size).
#version 3.7;

global_settings {
  assumed_gamma 1.0   // no gamma: the book writes clamp(round(c * 255))
  max_trace_level 6   // the camera ray and 5 reflections or refractions (depth 5)
  adc_bailout 0       // every level traced, however little it adds
  ambient_light rgb 1
}

// The book's camera: from (-2, 1, -4) to (0, 0.5, 0), a horizontal field of view of pi/3.
// Its view transform does not normalize the left vector (length 0.99381 here), which widens
// the view by 1/0.99381: tan(half angle) = tan(30 deg) / 0.99381.
camera {
  perspective
  location <-2, 1, -4>
  look_at <0, 0.5, 0>
  right x * image_width / image_height
  up y
  angle 2 * degrees(atan(tan(radians(30)) / 0.993807989999906))
}

light_source { <-5, 2.5, -3> color rgb <1, 1, 1> }

#declare SmallSphere = finish {
  ambient 0.1 diffuse 0.5 phong 0.8 phong_size 220 reflection { 0.4 }
}

// floor: reflective black and white checkers, 2-unit squares, at y = 0.01. The checkers are
// the book's: floor(x) + floor(y) + floor(z) even -> the first colour, the point taken just
// above the surface (its over point); the pattern is moved by half a square in y so that
// the surface lies inside one layer of it.
plane {
  y, 0
  texture {
    pigment { checker color rgb <1, 1, 1> color rgb <0, 0, 0> translate <0, -0.5, 0> scale 2 }
    finish { ambient 0.1 diffuse 0.9 phong 0.7 phong_size 240 reflection { 0.2 } }
  }
  translate <0, 0.01, 0>
}

// ceiling at y = 5, 1-unit checks, seen from below (the book's over point is just below)
plane {
  y, 0
  texture {
    pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <1, 1, 1> translate <0, 0.5, 0> }
    finish { ambient 0.5 diffuse 0.9 phong 0 }
  }
  translate <0, 5, 0>
}

// back wall: the book's rotation_x(pi/2) then translation(0, 0, 8), as a matrix (the
// object's y axis becomes the world's z); seen from the front, its over point is at object
// y just below 0
plane {
  y, 0
  texture {
    pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <1, 1, 1> translate <0, 0.5, 0> }
    finish { ambient 0.1 diffuse 0.9 phong 0.7 phong_size 200 }
  }
  matrix <1, 0, 0,  0, 0, 1,  0, -1, 0,  0, 0, 8>
}

// large glass sphere, radius 0.75, resting on the floor. It casts no shadow itself: POV-Ray
// lets light through a transparent object, where the book's glass casts a full shadow.
sphere {
  <-0.5, 0.75, 0.5>, 0.75
  texture {
    pigment { color rgbt <0.8, 0.8, 0.9, 1> }
    finish {
      ambient 0 diffuse 0.2 phong 0.9 phong_size 300
      reflection { 0, 0.3 fresnel on }
      conserve_energy
    }
  }
  interior { ior 1.57 }
  no_shadow
}

// ... its full shadow, cast by an opaque sphere that neither the camera nor a reflection
// sees: the glass sphere scaled by 1/2 about the light, so halfway to the light, where its
// shadow's cone is the glass sphere's (nothing else lies in that cone before the glass)
sphere {
  <-2.75, 1.625, -1.25>, 0.375
  pigment { color rgb 0 }
  no_image
  no_reflection
}

// red sphere behind the glass, radius 0.5
sphere {
  <-0.75, 0.5, 2>, 0.5
  texture {
    pigment { color rgb <1, 0, 0> }
    finish { ambient 0.1 diffuse 0.7 phong 0.9 phong_size 200 }
  }
}

// tan closed cylinder: the book's cylinder from y = 0 to 3, radius 1, scaled by
// (0.2, 0.4, 0.2): radius 0.2, from y = 0 to 1.2, at (1, 0, -1)
cylinder {
  <1, 0, -1>, <1, 1.2, -1>, 0.2
  texture {
    pigment { color rgb <1, 0.88, 0.63> }
    finish { ambient 0.1 diffuse 0.3 phong 0.9 phong_size 300 reflection { 0.3 } }
  }
}

// three small reflective spheres, radius 0.25
union {
  sphere { <-2, 0.25, -1>, 0.25 texture { pigment { color rgb <1, 0.1, 0.1> } finish { SmallSphere } } }
  sphere { <-1, 0.25, -1>, 0.25 texture { pigment { color rgb <0.1, 1, 0.1> } finish { SmallSphere } } }
  sphere { <0, 0.25, -1>, 0.25 texture { pigment { color rgb <0.1, 0.1, 1> } finish { SmallSphere } } }
}

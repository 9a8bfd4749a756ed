Feature: Materials
  A material describes how a surface reacts to light (the Phong model: ambient, diffuse and
  specular parts), plus its pattern, reflectivity and transparency.

  # `position` below is a variable (the point being lit); it hides the chapter-5 function
  # position(r, t).
  Background:
    Given m ← material()
      And position ← point(0, 0, 0)

  @chapter06
  Scenario: The settings of a new material
    Given m ← material()
    Then m.color = color(1, 1, 1)
      And m.ambient = 0.1
      And m.diffuse = 0.9
      And m.specular = 0.9
      And m.shininess = 200.0

  # Ambient 0.1 + diffuse 0.9 + specular 0.9 = 1.9.
  @chapter06
  Scenario: Eye directly between the light and the surface
    Given eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When result ← lighting(m, light, position, eyev, normalv)
    Then result = color(1.9, 1.9, 1.9)

  @chapter06
  Scenario: Eye raised 45 degrees above the line from the surface to the light
    Given eyev ← vector(0, √2/2, -√2/2)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When result ← lighting(m, light, position, eyev, normalv)
    Then result = color(1.0, 1.0, 1.0)

  @chapter06
  Scenario: Eye facing the surface with the light raised 45 degrees
    Given eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 10, -10), color(1, 1, 1))
    When result ← lighting(m, light, position, eyev, normalv)
    Then result = color(0.7364, 0.7364, 0.7364)

  @chapter06
  Scenario: Eye looking straight down the reflected light ray
    Given eyev ← vector(0, -√2/2, -√2/2)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 10, -10), color(1, 1, 1))
    When result ← lighting(m, light, position, eyev, normalv)
    Then result = color(1.6364, 1.6364, 1.6364)

  # Only the ambient part is left when the light is on the other side of the surface.
  @chapter06
  Scenario: A light behind the surface contributes only ambient light
    Given eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, 10), color(1, 1, 1))
    When result ← lighting(m, light, position, eyev, normalv)
    Then result = color(0.1, 0.1, 0.1)

  # The sixth argument says whether the point is in shadow (still the form without an object).
  @chapter08
  Scenario: A point in shadow receives only ambient light
    Given eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
      And in_shadow ← true
    When result ← lighting(m, light, position, eyev, normalv, in_shadow)
    Then result = color(0.1, 0.1, 0.1)

  # From chapter 10 lighting() also takes the object being lit (second argument), so that a
  # pattern can be placed in the object's space. in_shadow may be left out: it defaults to
  # false.
  @chapter10
  Scenario: A striped material lights each stripe in its own colour
    Given s ← sphere()
      And m.pattern ← stripe_pattern(color(1, 1, 1), color(0, 0, 0))
      And m.ambient ← 1
      And m.diffuse ← 0
      And m.specular ← 0
      And eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When c1 ← lighting(m, s, light, point(0.9, 0, 0), eyev, normalv, false)
      And c2 ← lighting(m, s, light, point(1.1, 0, 0), eyev, normalv)
    Then c1 = color(1, 1, 1)
      And c2 = color(0, 0, 0)

  @chapter11
  Scenario: A new material does not reflect
    Given m ← material()
    Then m.reflective = 0.0

  @chapter11
  Scenario: A new material is opaque and has the refractive index of a vacuum
    Given m ← material()
    Then m.transparency = 0.0
      And m.refractive_index = 1.0

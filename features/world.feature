Feature: World
  A world is a list of objects plus a light source. It finds everything a ray meets, shades
  hits (with shadows, reflection and refraction) and gives the colour seen along a ray.

  @chapter07
  Scenario: An empty world
    Given w ← world()
    Then w contains no objects
      And w has no light source

  # default_world() is the fixture used by most of the scenarios below: a light up and to
  # the left, an outer unit sphere with a greenish material, and an inner sphere of radius
  # 0.5 with the default material. The tuple in the table is a colour.
  @chapter07
  Scenario: The contents of the default world
    Given light ← point_light(point(-10, 10, -10), color(1, 1, 1))
      And s1 ← sphere() with:
        | material.color    | (0.8, 1.0, 0.6) |
        | material.diffuse  | 0.7             |
        | material.specular | 0.2             |
      And s2 ← sphere() with:
        | transform | scaling(0.5, 0.5, 0.5) |
    When w ← default_world()
    Then w.light = light
      And w contains s1
      And w contains s2

  # The list covers every object and is sorted by t.
  @chapter07
  Scenario: A ray meets every object in the world
    Given w ← default_world()
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
    When xs ← intersect_world(w, r)
    Then xs.count = 4
      And xs[0].t = 4
      And xs[1].t = 4.5
      And xs[2].t = 5.5
      And xs[3].t = 6

  @chapter07
  Scenario: Shading a hit on the outside of an object
    Given w ← default_world()
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← the first object in w
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then c = color(0.38066, 0.47583, 0.2855)

  @chapter07
  Scenario: Shading a hit seen from inside an object
    Given w ← default_world()
      And w.light ← point_light(point(0, 0.25, 0), color(1, 1, 1))
      And r ← ray(point(0, 0, 0), vector(0, 0, 1))
      And shape ← the second object in w
      And i ← intersection(0.5, shape)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then c = color(0.90498, 0.90498, 0.90498)

  @chapter07
  Scenario: A ray that meets nothing is black
    Given w ← default_world()
      And r ← ray(point(0, 0, -5), vector(0, 1, 0))
    When c ← color_at(w, r)
    Then c = color(0, 0, 0)

  @chapter07
  Scenario: A ray that meets an object takes the shaded colour of the hit
    Given w ← default_world()
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
    When c ← color_at(w, r)
    Then c = color(0.38066, 0.47583, 0.2855)

  # The ray starts between the two spheres and points at the inner one; the outer sphere's
  # intersection behind the ray must not be used. With ambient 1 the inner sphere shows
  # its plain colour.
  @chapter07
  Scenario: An intersection behind the ray is ignored
    Given w ← default_world()
      And outer ← the first object in w
      And outer.material.ambient ← 1
      And inner ← the second object in w
      And inner.material.ambient ← 1
      And r ← ray(point(0, 0, 0.75), vector(0, 0, -1))
    When c ← color_at(w, r)
    Then c = inner.material.color

  @chapter08
  Scenario: A point with nothing in line with it and the light is lit
    Given w ← default_world()
      And p ← point(0, 10, 0)
    Then is_shadowed(w, p) is false

  @chapter08
  Scenario: A point with an object between it and the light is in shadow
    Given w ← default_world()
      And p ← point(10, -10, 10)
    Then is_shadowed(w, p) is true

  @chapter08
  Scenario: An object on the far side of the light casts no shadow on the point
    Given w ← default_world()
      And p ← point(-20, 20, -20)
    Then is_shadowed(w, p) is false

  @chapter08
  Scenario: An object behind the point casts no shadow on it
    Given w ← default_world()
      And p ← point(-2, 2, -2)
    Then is_shadowed(w, p) is false

  @chapter08
  Scenario: shade_hit() leaves only ambient light on a shadowed point
    Given w ← world()
      And w.light ← point_light(point(0, 0, -10), color(1, 1, 1))
      And s1 ← sphere()
      And s1 is added to w
      And s2 ← sphere() with:
        | transform | translation(0, 0, 10) |
      And s2 is added to w
      And r ← ray(point(0, 0, 5), vector(0, 0, 1))
      And i ← intersection(4, s2)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then c = color(0.1, 0.1, 0.1)

  # From here on a variable called `color` holds a result, while color(...) in call
  # position is still the colour constructor.
  @chapter11
  Scenario: A surface that does not reflect adds no reflected colour
    Given w ← default_world()
      And r ← ray(point(0, 0, 0), vector(0, 0, 1))
      And shape ← the second object in w
      And shape.material.ambient ← 1
      And i ← intersection(1, shape)
    When comps ← prepare_computations(i, r)
      And color ← reflected_color(w, comps)
    Then color = color(0, 0, 0)

  @chapter11
  Scenario: A half-mirror floor reflects the spheres above it
    Given w ← default_world()
      And shape ← plane() with:
        | material.reflective | 0.5                   |
        | transform           | translation(0, -1, 0) |
      And shape is added to w
      And r ← ray(point(0, 0, -3), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, shape)
    When comps ← prepare_computations(i, r)
      And color ← reflected_color(w, comps)
    Then color = color(0.19032, 0.2379, 0.14274)

  @chapter11
  Scenario: shade_hit() adds the reflected colour to the surface colour
    Given w ← default_world()
      And shape ← plane() with:
        | material.reflective | 0.5                   |
        | transform           | translation(0, -1, 0) |
      And shape is added to w
      And r ← ray(point(0, 0, -3), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, shape)
    When comps ← prepare_computations(i, r)
      And color ← shade_hit(w, comps)
    Then color = color(0.87677, 0.92436, 0.82918)

  # Two parallel mirrors bounce the ray back and forth for ever unless the recursion is
  # limited; this only checks that color_at() returns at all.
  @chapter11
  Scenario: Two facing mirrors do not trap color_at() in endless recursion
    Given w ← world()
      And w.light ← point_light(point(0, 0, 0), color(1, 1, 1))
      And lower ← plane() with:
        | material.reflective | 1                     |
        | transform           | translation(0, -1, 0) |
      And lower is added to w
      And upper ← plane() with:
        | material.reflective | 1                    |
        | transform           | translation(0, 1, 0) |
      And upper is added to w
      And r ← ray(point(0, 0, 0), vector(0, 1, 0))
    Then color_at(w, r) should terminate successfully

  # The third argument is the number of bounces still allowed.
  @chapter11
  Scenario: No reflected colour once the bounce budget is used up
    Given w ← default_world()
      And shape ← plane() with:
        | material.reflective | 0.5                   |
        | transform           | translation(0, -1, 0) |
      And shape is added to w
      And r ← ray(point(0, 0, -3), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, shape)
    When comps ← prepare_computations(i, r)
      And color ← reflected_color(w, comps, 0)
    Then color = color(0, 0, 0)

  @chapter11
  Scenario: An opaque surface adds no refracted colour
    Given w ← default_world()
      And shape ← the first object in w
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And xs ← intersections(4:shape, 6:shape)
    When comps ← prepare_computations(xs[0], r, xs)
      And c ← refracted_color(w, comps, 5)
    Then c = color(0, 0, 0)

  @chapter11
  Scenario: No refracted colour once the bounce budget is used up
    Given w ← default_world()
      And shape ← the first object in w
      And shape has:
        | material.transparency     | 1.0 |
        | material.refractive_index | 1.5 |
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And xs ← intersections(4:shape, 6:shape)
    When comps ← prepare_computations(xs[0], r, xs)
      And c ← refracted_color(w, comps, 0)
    Then c = color(0, 0, 0)

  # The ray starts inside the sphere, so the intersection that matters is xs[1], the one
  # ahead of it.
  @chapter11
  Scenario: Total internal reflection leaves no refracted colour
    Given w ← default_world()
      And shape ← the first object in w
      And shape has:
        | material.transparency     | 1.0 |
        | material.refractive_index | 1.5 |
      And r ← ray(point(0, 0, √2/2), vector(0, 1, 0))
      And xs ← intersections(-√2/2:shape, √2/2:shape)
    When comps ← prepare_computations(xs[1], r, xs)
      And c ← refracted_color(w, comps, 5)
    Then c = color(0, 0, 0)

  # test_pattern() colours each point with its own coordinates, so the result shows where
  # the refracted ray landed on the outer sphere.
  @chapter11
  Scenario: A refracted ray picks up the colour of what lies behind the surface
    Given w ← default_world()
      And A ← the first object in w
      And A has:
        | material.ambient | 1.0            |
        | material.pattern | test_pattern() |
      And B ← the second object in w
      And B has:
        | material.transparency     | 1.0 |
        | material.refractive_index | 1.5 |
      And r ← ray(point(0, 0, 0.1), vector(0, 1, 0))
      And xs ← intersections(-0.9899:A, -0.4899:B, 0.4899:B, 0.9899:A)
    When comps ← prepare_computations(xs[2], r, xs)
      And c ← refracted_color(w, comps, 5)
    Then c = color(0, 0.99888, 0.04725)

  @chapter11
  Scenario: shade_hit() adds the refracted colour of a see-through floor
    Given w ← default_world()
      And floor ← plane() with:
        | transform                 | translation(0, -1, 0) |
        | material.transparency     | 0.5                   |
        | material.refractive_index | 1.5                   |
      And floor is added to w
      And ball ← sphere() with:
        | material.color   | (1, 0, 0)                  |
        | material.ambient | 0.5                        |
        | transform        | translation(0, -3.5, -0.5) |
      And ball is added to w
      And r ← ray(point(0, 0, -3), vector(0, -√2/2, √2/2))
      And xs ← intersections(√2:floor)
    When comps ← prepare_computations(xs[0], r, xs)
      And color ← shade_hit(w, comps, 5)
    Then color = color(0.93642, 0.68642, 0.68642)

  # With both reflection and transparency, the Schlick reflectance decides how to mix the
  # reflected and refracted colours.
  @chapter11
  Scenario: shade_hit() mixes reflection and refraction on a glassy floor
    Given w ← default_world()
      And r ← ray(point(0, 0, -3), vector(0, -√2/2, √2/2))
      And floor ← plane() with:
        | transform                 | translation(0, -1, 0) |
        | material.reflective       | 0.5                   |
        | material.transparency     | 0.5                   |
        | material.refractive_index | 1.5                   |
      And floor is added to w
      And ball ← sphere() with:
        | material.color   | (1, 0, 0)                  |
        | material.ambient | 0.5                        |
        | transform        | translation(0, -3.5, -0.5) |
      And ball is added to w
      And xs ← intersections(√2:floor)
    When comps ← prepare_computations(xs[0], r, xs)
      And color ← shade_hit(w, comps, 5)
    Then color = color(0.93391, 0.69643, 0.69243)

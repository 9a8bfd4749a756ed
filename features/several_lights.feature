Feature: Several lights
  The book's world has one light; its published scenes light theirs with several. A world
  holds a list of lights; each one adds its own diffuse and specular light, with its own
  shadow test, and the ambient light is counted once, with the first. `w.light` is still the
  book's notation: the first light.

  @chapter07
  Scenario: A new world has no lights
    Given w ← world()
    Then w.lights is empty
      And w has no light source

  @chapter07
  Scenario: A light added to a world goes after the ones it has
    Given w ← default_world()
      And light2 ← point_light(point(10, 10, -10), color(0.5, 0.5, 0.5))
    When light2 is added to w
    Then w.lights[1] = light2
      And w.light = point_light(point(-10, 10, -10), color(1, 1, 1))

  # w.light ← ... keeps the book's meaning in a world of one light, and replaces only the
  # first light of a world with several.
  @chapter07
  Scenario: Setting the world's light replaces its first light
    Given w ← default_world()
      And light2 ← point_light(point(10, 10, -10), color(0.5, 0.5, 0.5))
      And light2 is added to w
    When w.light ← point_light(point(0, 0, -10), color(1, 1, 1))
    Then w.lights[0] = point_light(point(0, 0, -10), color(1, 1, 1))
      And w.lights[1] = light2

  @chapter07
  Scenario: lighting() can leave the ambient term out
    Given m ← material()
      And position ← point(0, 0, 0)
      And eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When lit ← lighting(m, sphere(), light, position, eyev, normalv, false, false)
      And shadowed ← lighting(m, sphere(), light, position, eyev, normalv, true, false)
    Then lit = color(1.8, 1.8, 1.8)
      And shadowed = color(0, 0, 0)

  # The default world's light twice: the second copy adds everything but the ambient term
  # (0.1 of the outer sphere's color (0.8, 1.0, 0.6)).
  @chapter07
  Scenario: A second light adds its diffuse and specular light, not its ambient
    Given w ← default_world()
      And w.light is added to w
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← the first object in w
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then c = color(0.68132, 0.85166, 0.511)

  # Chapter 8's point in shadow, lit by a second light between the two spheres.
  @chapter08
  Scenario: A point in the shadow of one light is still lit by another
    Given w ← world()
      And w.light ← point_light(point(0, 0, -10), color(1, 1, 1))
      And s1 ← sphere()
      And s1 is added to w
      And s2 ← sphere() with:
        | transform | translation(0, 0, 10) |
      And s2 is added to w
      And point_light(point(0, 0, 5), color(0.5, 0.5, 0.5)) is added to w
      And r ← ray(point(0, 0, 5), vector(0, 0, 1))
      And i ← intersection(4, s2)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then is_shadowed(w, comps.over_point) is true
      And is_shadowed(w, point(0, 0, 5), comps.over_point) is false
      And c = color(1, 1, 1)

  @chapter08
  Scenario Outline: is_shadowed() between a point and any light position
    Given w ← default_world()
      And light_position ← point(-10, 10, -10)
      And p ← <point>
    Then is_shadowed(w, light_position, p) is <result>

    Examples:
      | point               | result |
      | point(0, 10, 0)     | false  |
      | point(10, -10, 10)  | true   |
      | point(-20, 20, -20) | false  |
      | point(-2, 2, -2)    | false  |

  @chapter07
  Scenario: A world without a light shades every point black
    Given w ← default_world()
      And w.light ← nothing
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
    When c ← color_at(w, r)
    Then w.lights is empty
      And c = color(0, 0, 0)

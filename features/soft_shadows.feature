Feature: Soft shadows
  A point light has no size, so its shadows have hard edges. An area light is a
  parallelogram cut into cells, each one a point of light: a point sees some of the cells
  and not others, and is lit in proportion, so the edge of a shadow fades out. The cells
  are walked v outer, u inner; where inside its cell each point lies comes from the
  light's jitter sequence, two values per point. lighting() takes the fraction of the light
  that arrives where the book had in_shadow, and still takes true and false.
  (The book's online bonus chapter "Rendering soft shadows", numbered 18 here.)

  # is_shadowed() between any two points: the default world's spheres sit at the origin,
  # the light position is across the world from the second example.
  @chapter18
  Scenario Outline: is_shadowed() looks for blockers between a point and a light position
    Given w ← default_world()
      And light_position ← point(-10, -10, -10)
      And p ← <point>
    Then is_shadowed(w, light_position, p) is <result>

    Examples:
      | point                | result |
      | point(-10, -10, 10)  | false  |
      | point(10, 10, 10)    | true   |
      | point(-20, -20, -20) | false  |
      | point(-5, -5, -5)    | false  |

  # A point light is all or nothing: the default world's light is up and to the left.
  @chapter18
  Scenario Outline: A point light reaches a point fully or not at all
    Given w ← default_world()
      And light ← w.light
      And pt ← <point>
    When intensity ← intensity_at(light, pt, w)
    Then intensity = <result>

    Examples:
      | point                | result |
      | point(0, 1.0001, 0)  | 1.0    |
      | point(-1.0001, 0, 0) | 1.0    |
      | point(0, 0, -1.0001) | 1.0    |
      | point(0, 0, 1.0001)  | 0.0    |
      | point(1.0001, 0, 0)  | 0.0    |
      | point(0, -1.0001, 0) | 0.0    |
      | point(0, 0, 0)       | 0.0    |

  # The fraction of the light that arrives scales the diffuse and specular terms; the
  # ambient term stays.
  @chapter18
  Scenario Outline: lighting() scales a point light by the fraction that arrives
    Given w ← default_world()
      And w.light ← point_light(point(0, 0, -10), color(1, 1, 1))
      And shape ← the first object in w
      And shape.material.ambient ← 0.1
      And shape.material.diffuse ← 0.9
      And shape.material.specular ← 0
      And shape.material.color ← color(1, 1, 1)
      And pt ← point(0, 0, -1)
      And eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
    When result ← lighting(shape.material, shape, w.light, pt, eyev, normalv, <intensity>)
    Then result = <result>

    Examples:
      | intensity | result                  |
      | 1.0       | color(1, 1, 1)          |
      | 0.5       | color(0.55, 0.55, 0.55) |
      | 0.0       | color(0.1, 0.1, 0.1)    |

  # The book's in_shadow still means what it meant: true is no light, false all of it.
  @chapter18
  Scenario: lighting() still takes in_shadow as true or false
    Given m ← material()
      And pt ← point(0, 0, 0)
      And eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When shadowed ← lighting(m, sphere(), light, pt, eyev, normalv, true)
      And lit ← lighting(m, sphere(), light, pt, eyev, normalv, false)
    Then shadowed = color(0.1, 0.1, 0.1)
      And shadowed = lighting(m, sphere(), light, pt, eyev, normalv, 0.0)
      And lit = color(1.9, 1.9, 1.9)
      And lit = lighting(m, sphere(), light, pt, eyev, normalv, 1.0)

  # The edges given are the whole light's; the light keeps one cell's.
  @chapter18
  Scenario: An area light knows its corner, its cells and its centre
    Given corner ← point(0, 0, 0)
      And v1 ← vector(2, 0, 0)
      And v2 ← vector(0, 0, 1)
    When light ← area_light(corner, v1, 4, v2, 2, color(1, 1, 1))
    Then light.corner = corner
      And light.uvec = vector(0.5, 0, 0)
      And light.usteps = 4
      And light.vvec = vector(0, 0, 0.5)
      And light.vsteps = 2
      And light.samples = 8
      And light.position = point(1, 0, 0.5)
      And light.intensity = color(1, 1, 1)

  @chapter18
  Scenario Outline: An area light needs at least one whole cell along each edge
    Given corner ← point(0, 0, 0)
    Then area_light(corner, <uvec>, <usteps>, vector(0, 0, 1), 2, color(1, 1, 1)) should fail

    Examples:
      | uvec            | usteps |
      | vector(2, 0, 0) | 0      |
      | vector(2, 0, 0) | -1     |
      | vector(2, 0, 0) | 2.5    |
      | vector(0, 0, 0) | 4      |

  # Unless told otherwise, each cell's point is its centre.
  @chapter18
  Scenario Outline: A point on an area light is the centre of its cell
    Given corner ← point(0, 0, 0)
      And v1 ← vector(2, 0, 0)
      And v2 ← vector(0, 0, 1)
      And light ← area_light(corner, v1, 4, v2, 2, color(1, 1, 1))
    When pt ← point_on_light(light, <u>, <v>)
    Then pt = <result>

    Examples:
      | u | v | result               |
      | 0 | 0 | point(0.25, 0, 0.25) |
      | 1 | 0 | point(0.75, 0, 0.25) |
      | 0 | 1 | point(0.25, 0, 0.75) |
      | 2 | 0 | point(1.25, 0, 0.25) |
      | 3 | 1 | point(1.75, 0, 0.75) |

  # A light 2x2 cells wide in front of the default world: the outer sphere hides more of
  # it the further behind the sphere the point is.
  @chapter18
  Scenario Outline: An area light reaches a point through the cells it can see
    Given w ← default_world()
      And corner ← point(-0.5, -0.5, -5)
      And v1 ← vector(1, 0, 0)
      And v2 ← vector(0, 1, 0)
      And light ← area_light(corner, v1, 2, v2, 2, color(1, 1, 1))
      And pt ← <point>
    When intensity ← intensity_at(light, pt, w)
    Then intensity = <result>

    Examples:
      | point                | result |
      | point(0, 0, 2)       | 0.0    |
      | point(1, -1, 2)      | 0.25   |
      | point(1.5, 0, 2)     | 0.5    |
      | point(1.25, 1.25, 3) | 0.75   |
      | point(0, 0, -2)      | 1.0    |

  # The chapter's stand-in for random numbers: a fixed list, given out in turn, forever.
  @chapter18
  Scenario: A sequence gives its numbers in turn and starts over
    Given gen ← sequence(0.1, 0.5, 1.0)
    Then next(gen) = 0.1
      And next(gen) = 0.5
      And next(gen) = 1.0
      And next(gen) = 0.1
      And next(gen) = 0.5

  # Each point takes two numbers of the sequence: how far along u, then along v, inside
  # its cell.
  @chapter18
  Scenario Outline: The jitter sequence moves a point inside its cell
    Given corner ← point(0, 0, 0)
      And v1 ← vector(2, 0, 0)
      And v2 ← vector(0, 0, 1)
      And light ← area_light(corner, v1, 4, v2, 2, color(1, 1, 1))
      And light.jitter_by ← sequence(0.3, 0.7)
    When pt ← point_on_light(light, <u>, <v>)
    Then pt = <result>

    Examples:
      | u | v | result               |
      | 0 | 0 | point(0.15, 0, 0.35) |
      | 1 | 0 | point(0.65, 0, 0.35) |
      | 0 | 1 | point(0.15, 0, 0.85) |
      | 2 | 0 | point(1.15, 0, 0.35) |
      | 3 | 1 | point(1.65, 0, 0.85) |

  # The same light and points as above, with the cells' points moved: the sequence has
  # five numbers and the four cells take eight, in order.
  @chapter18
  Scenario Outline: An area light with jittered points reaches a point through the cells it can see
    Given w ← default_world()
      And corner ← point(-0.5, -0.5, -5)
      And v1 ← vector(1, 0, 0)
      And v2 ← vector(0, 1, 0)
      And light ← area_light(corner, v1, 2, v2, 2, color(1, 1, 1))
      And light.jitter_by ← sequence(0.7, 0.3, 0.9, 0.1, 0.5)
      And pt ← <point>
    When intensity ← intensity_at(light, pt, w)
    Then intensity = <result>

    Examples:
      | point                | result |
      | point(0, 0, 2)       | 0.0    |
      | point(1, -1, 2)      | 0.5    |
      | point(1.5, 0, 2)     | 0.75   |
      | point(1.25, 1.25, 3) | 0.75   |
      | point(0, 0, -2)      | 1.0    |

  # Every cell lights the point from its own direction: the diffuse and specular terms
  # are the mean over the cells.
  @chapter18
  Scenario Outline: lighting() averages an area light over its cells
    Given corner ← point(-0.5, -0.5, -5)
      And v1 ← vector(1, 0, 0)
      And v2 ← vector(0, 1, 0)
      And light ← area_light(corner, v1, 2, v2, 2, color(1, 1, 1))
      And shape ← sphere()
      And shape.material.ambient ← 0.1
      And shape.material.diffuse ← 0.9
      And shape.material.specular ← 0
      And shape.material.color ← color(1, 1, 1)
      And eye ← point(0, 0, -5)
      And pt ← <point>
      And eyev ← normalize(eye - pt)
      And normalv ← vector(pt.x, pt.y, pt.z)
    When result ← lighting(shape.material, shape, light, pt, eyev, normalv, 1.0)
    Then result = <result>

    Examples:
      | point                     | result                        |
      | point(0, 0, -1)           | color(0.9965, 0.9965, 0.9965) |
      | point(0, 0.7071, -0.7071) | color(0.6232, 0.6232, 0.6232) |

  # Half the light arriving halves the averaged terms; none leaves the ambient term, as
  # in_shadow true does.
  @chapter18
  Scenario Outline: lighting() scales an area light by the fraction that arrives
    Given corner ← point(-0.5, -0.5, -5)
      And light ← area_light(corner, vector(1, 0, 0), 2, vector(0, 1, 0), 2, color(1, 1, 1))
      And m ← material()
      And m.specular ← 0
      And pt ← point(0, 0, -1)
    When result ← lighting(m, sphere(), light, pt, vector(0, 0, -1), vector(0, 0, -1), <in_shadow>)
    Then result = <result>

    Examples:
      | in_shadow | result                        |
      | 1.0       | color(0.9965, 0.9965, 0.9965) |
      | 0.5       | color(0.54825, 0.54825, 0.54825) |
      | 0.0       | color(0.1, 0.1, 0.1)          |
      | true      | color(0.1, 0.1, 0.1)          |

  # A one-cell light at a point is a point light there.
  @chapter18
  Scenario: A world lit by a one-cell area light shades as with a point light at its centre
    Given w ← default_world()
      And w.light ← area_light(point(-10.5, 10, -10.5), vector(1, 0, 0), 1, vector(0, 0, 1), 1, color(1, 1, 1))
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← the first object in w
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
      And c ← shade_hit(w, comps)
    Then w.light.position = point(-10, 10, -10)
      And c = color(0.38066, 0.47583, 0.2855)

  # The default world's light over a 4x4 square: the inner sphere is hidden by the outer
  # one, so a point on it sees no cell; the point on the outer sphere sees them all.
  @chapter18
  Scenario: shade_hit() takes each light's share from intensity_at()
    Given w ← default_world()
      And w.light ← area_light(point(-12, 10, -12), vector(4, 0, 0), 4, vector(0, 0, 4), 4, color(1, 1, 1))
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And outer ← the first object in w
      And inner ← the second object in w
    When comps ← prepare_computations(intersection(4, outer), r)
      And c ← shade_hit(w, comps)
    Then intensity_at(w.light, comps.over_point, w) = 1.0
      And intensity_at(w.light, point(0, 0, -0.5001), w) = 0.0
      And c = lighting(outer.material, outer, w.light, comps.over_point, comps.eyev, comps.normalv, 1.0)

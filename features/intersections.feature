Feature: Intersections
  Where a ray meets an object: intersection records and lists of them, picking the visible
  hit, and the values precomputed at a hit for shading, reflection and refraction.

  @chapter05
  Scenario: An intersection holds a distance and an object
    Given s ← sphere()
    When i ← intersection(3.5, s)
    Then i.t = 3.5
      And i.object = s

  @chapter05
  Scenario: Collecting intersections into a list
    Given s ← sphere()
      And i1 ← intersection(1, s)
      And i2 ← intersection(2, s)
    When xs ← intersections(i1, i2)
    Then xs.count = 2
      And xs[0].t = 1
      And xs[1].t = 2

  @chapter05
  Scenario: With only positive distances the hit is the nearest
    Given s ← sphere()
      And i1 ← intersection(1, s)
      And i2 ← intersection(2, s)
      And xs ← intersections(i2, i1)
    When i ← hit(xs)
    Then i = i1

  @chapter05
  Scenario: Negative distances are skipped when choosing the hit
    Given s ← sphere()
      And i1 ← intersection(-1, s)
      And i2 ← intersection(1, s)
      And xs ← intersections(i2, i1)
    When i ← hit(xs)
    Then i = i2

  @chapter05
  Scenario: With only negative distances there is no hit
    Given s ← sphere()
      And i1 ← intersection(-2, s)
      And i2 ← intersection(-1, s)
      And xs ← intersections(i2, i1)
    When i ← hit(xs)
    Then i is nothing

  # intersections() may be given its arguments in any order.
  @chapter05
  Scenario: The hit is the smallest distance that is not negative
    Given s ← sphere()
      And i1 ← intersection(5, s)
      And i2 ← intersection(7, s)
      And i3 ← intersection(-3, s)
      And i4 ← intersection(2, s)
      And xs ← intersections(i1, i2, i3, i4)
    When i ← hit(xs)
    Then i = i4

  @chapter07
  Scenario: Preparing the shading values for an intersection
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← sphere()
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
    Then comps.t = i.t
      And comps.object = i.object
      And comps.point = point(0, 0, -1)
      And comps.eyev = vector(0, 0, -1)
      And comps.normalv = vector(0, 0, -1)

  @chapter07
  Scenario: A hit on the outside of an object is not inside
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← sphere()
      And i ← intersection(4, shape)
    When comps ← prepare_computations(i, r)
    Then comps.inside = false

  # From inside, the surface normal (0, 0, 1) points away from the eye, so it is flipped.
  @chapter07
  Scenario: A hit seen from inside an object flips the normal
    Given r ← ray(point(0, 0, 0), vector(0, 0, 1))
      And shape ← sphere()
      And i ← intersection(1, shape)
    When comps ← prepare_computations(i, r)
    Then comps.point = point(0, 0, 1)
      And comps.eyev = vector(0, 0, -1)
      And comps.inside = true
      And comps.normalv = vector(0, 0, -1)

  # over_point sits a hair above the surface so that the shadow ray does not hit the surface
  # it starts from (acne).
  @chapter08
  Scenario: The shadow starting point is nudged off the surface
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← sphere() with:
        | transform | translation(0, 0, 1) |
      And i ← intersection(5, shape)
    When comps ← prepare_computations(i, r)
    Then comps.over_point.z < -EPSILON/2
      And comps.point.z > comps.over_point.z

  @chapter11
  Scenario: Preparing the direction of the reflected ray
    Given shape ← plane()
      And r ← ray(point(0, 1, -1), vector(0, -√2/2, √2/2))
      And i ← intersection(√2, shape)
    When comps ← prepare_computations(i, r)
    Then comps.reflectv = vector(0, √2/2, √2/2)

  # Three overlapping glass spheres: A encloses B and C, which overlap each other.
  # `2:A` is shorthand for intersection(2, A). n1 is the index of the material the ray
  # leaves and n2 of the material it enters at each intersection.
  @chapter11
  Scenario Outline: The refractive indices on both sides of each intersection
    Given A ← glass_sphere() with:
        | transform                 | scaling(2, 2, 2) |
        | material.refractive_index | 1.5              |
      And B ← glass_sphere() with:
        | transform                 | translation(0, 0, -0.25) |
        | material.refractive_index | 2.0                      |
      And C ← glass_sphere() with:
        | transform                 | translation(0, 0, 0.25) |
        | material.refractive_index | 2.5                     |
      And r ← ray(point(0, 0, -4), vector(0, 0, 1))
      And xs ← intersections(2:A, 2.75:B, 3.25:C, 4.75:B, 5.25:C, 6:A)
    When comps ← prepare_computations(xs[<index>], r, xs)
    Then comps.n1 = <n1>
      And comps.n2 = <n2>

    Examples:
      | index | n1  | n2  |
      | 0     | 1.0 | 1.5 |
      | 1     | 1.5 | 2.0 |
      | 2     | 2.0 | 2.5 |
      | 3     | 2.5 | 2.5 |
      | 4     | 2.5 | 1.5 |
      | 5     | 1.5 | 1.0 |

  # under_point sits a hair below the surface: refracted rays start there.
  @chapter11
  Scenario: The refraction starting point is nudged under the surface
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And shape ← glass_sphere() with:
        | transform | translation(0, 0, 1) |
      And i ← intersection(5, shape)
      And xs ← intersections(i)
    When comps ← prepare_computations(i, r, xs)
    Then comps.under_point.z > EPSILON/2
      And comps.point.z < comps.under_point.z

  # The ray starts inside the sphere, so the interesting intersection is xs[1].
  @chapter11
  Scenario: Schlick's reflectance is total when all light is reflected internally
    Given shape ← glass_sphere()
      And r ← ray(point(0, 0, √2/2), vector(0, 1, 0))
      And xs ← intersections(-√2/2:shape, √2/2:shape)
    When comps ← prepare_computations(xs[1], r, xs)
      And reflectance ← schlick(comps)
    Then reflectance = 1.0

  @chapter11
  Scenario: Schlick's reflectance is small when looking straight at the surface
    Given shape ← glass_sphere()
      And r ← ray(point(0, 0, 0), vector(0, 1, 0))
      And xs ← intersections(-1:shape, 1:shape)
    When comps ← prepare_computations(xs[1], r, xs)
      And reflectance ← schlick(comps)
    Then reflectance = 0.04

  @chapter11
  Scenario: Schlick's reflectance at a grazing angle going into denser glass
    Given shape ← glass_sphere()
      And r ← ray(point(0, 0.99, -2), vector(0, 0, 1))
      And xs ← intersections(1.8589:shape)
    When comps ← prepare_computations(xs[0], r, xs)
      And reflectance ← schlick(comps)
    Then reflectance = 0.48873

  # Triangles (and smooth triangles) remember where on their surface a ray hit them.
  @chapter15
  Scenario: An intersection can also hold u and v
    Given s ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
    When i ← intersection_with_uv(3.5, s, 0.2, 0.4)
    Then i.u = 0.2
      And i.v = 0.4

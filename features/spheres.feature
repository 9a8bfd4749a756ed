Feature: Spheres
  The unit sphere at the origin: where rays meet it, how a transformation moves it, the
  normal vector on its surface, and the material it carries.

  # xs[0] = 4.0 compares the intersection's t with the number.
  @chapter05
  Scenario: A ray through the middle of a sphere meets it twice
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0] = 4.0
      And xs[1] = 6.0

  # A grazing ray still reports two intersections, both at the same t.
  @chapter05
  Scenario: A ray that grazes a sphere meets it at one point twice
    Given r ← ray(point(0, 1, -5), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0] = 5.0
      And xs[1] = 5.0

  @chapter05
  Scenario: A ray that passes above a sphere meets nothing
    Given r ← ray(point(0, 2, -5), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 0

  # The intersection behind the origin has a negative t and is still reported.
  @chapter05
  Scenario: A ray starting at the centre of a sphere meets it behind and ahead
    Given r ← ray(point(0, 0, 0), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0] = -1.0
      And xs[1] = 1.0

  @chapter05
  Scenario: A sphere lying entirely behind the ray
    Given r ← ray(point(0, 0, 5), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0] = -6.0
      And xs[1] = -4.0

  @chapter05
  Scenario: Each intersection records the sphere it belongs to
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← sphere()
    When xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0].object = s
      And xs[1].object = s

  @chapter05
  Scenario: A new sphere has no transformation
    Given s ← sphere()
    Then s.transform = identity_matrix

  @chapter05
  Scenario: A sphere's transformation can be replaced
    Given s ← sphere()
      And t ← translation(2, 3, 4)
    When set_transform(s, t)
    Then s.transform = t

  # The ray is moved into the sphere's own space, but the t values still measure the
  # original ray.
  @chapter05
  Scenario: A ray meets a sphere that has been scaled up
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← sphere()
    When set_transform(s, scaling(2, 2, 2))
      And xs ← intersect(s, r)
    Then xs.count = 2
      And xs[0].t = 3
      And xs[1].t = 7

  @chapter05
  Scenario: A ray misses a sphere that has been moved aside
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← sphere()
    When set_transform(s, translation(5, 0, 0))
      And xs ← intersect(s, r)
    Then xs.count = 0

  @chapter06
  Scenario: The normal where the x axis pierces the sphere
    Given s ← sphere()
    When n ← normal_at(s, point(1, 0, 0))
    Then n = vector(1, 0, 0)

  @chapter06
  Scenario: The normal where the y axis pierces the sphere
    Given s ← sphere()
    When n ← normal_at(s, point(0, 1, 0))
    Then n = vector(0, 1, 0)

  @chapter06
  Scenario: The normal where the z axis pierces the sphere
    Given s ← sphere()
    When n ← normal_at(s, point(0, 0, 1))
    Then n = vector(0, 0, 1)

  @chapter06
  Scenario: The normal at a point on no axis
    Given s ← sphere()
    When n ← normal_at(s, point(√3/3, √3/3, √3/3))
    Then n = vector(√3/3, √3/3, √3/3)

  @chapter06
  Scenario: A sphere's normal always has length one
    Given s ← sphere()
    When n ← normal_at(s, point(√3/3, √3/3, √3/3))
    Then n = normalize(n)

  @chapter06
  Scenario: The normal on a sphere that has been moved
    Given s ← sphere()
      And set_transform(s, translation(0, 1, 0))
    When n ← normal_at(s, point(0, 1.70711, -0.70711))
    Then n = vector(0, 0.70711, -0.70711)

  # The object-space normal is carried back to world space by the transposed inverse of the
  # transformation, then normalized.
  @chapter06
  Scenario: The normal on a sphere that has been squashed and turned
    Given s ← sphere()
      And m ← scaling(1, 0.5, 1) * rotation_z(π/5)
      And set_transform(s, m)
    When n ← normal_at(s, point(0, √2/2, -√2/2))
    Then n = vector(0, 0.97014, -0.24254)

  @chapter06
  Scenario: A new sphere has the default material
    Given s ← sphere()
    When m ← s.material
    Then m = material()

  @chapter06
  Scenario: A sphere's material can be replaced
    Given s ← sphere()
      And m ← material()
      And m.ambient ← 1
    When s.material ← m
    Then s.material = m

  @chapter11
  Scenario: glass_sphere() makes a sphere of clear glass
    Given s ← glass_sphere()
    Then s.transform = identity_matrix
      And s.material.transparency = 1.0
      And s.material.refractive_index = 1.5

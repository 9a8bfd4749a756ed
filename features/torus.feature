Feature: Tori
  Beyond the book: a tube of radius minor_radius around a circle of radius major_radius,
  the circle in the xz plane, centred on the origin. A ray meets it where a quartic in t
  vanishes: up to four times.

  @chapter20
  Scenario: A new torus has a tube of 0.25 around a circle of 1
    Given t ← torus()
    Then t.major_radius = 1
      And t.minor_radius = 0.25

  # Through the hole along the axis, over the top, beside it, and past its rim.
  @chapter20
  Scenario Outline: Rays that miss a torus
    Given t ← torus()
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    When xs ← local_intersect(t, r)
    Then xs.count = 0

    Examples:
      | origin             | direction        |
      | point(0, 3, 0)     | vector(0, -1, 0) |
      | point(-3, 0.5, 0)  | vector(1, 0, 0)  |
      | point(1.5, 3, 0)   | vector(0, -1, 0) |
      | point(-3, 0, 1.5)  | vector(1, 0, 0)  |

  # Across the whole torus through its centre: in and out of the tube on both sides.
  @chapter20
  Scenario Outline: A ray across the torus meets it four times
    Given t ← torus()
      And r ← ray(<origin>, <direction>)
    When xs ← local_intersect(t, r)
    Then xs.count = 4
      And xs[0].t = 1.75
      And xs[1].t = 2.25
      And xs[2].t = 3.75
      And xs[3].t = 4.25

    Examples:
      | origin          | direction       |
      | point(-3, 0, 0) | vector(1, 0, 0) |
      | point(0, 0, -3) | vector(0, 0, 1) |

  @chapter20
  Scenario: A ray down through the tube meets it twice
    Given t ← torus()
      And r ← ray(point(1, 3, 0), vector(0, -1, 0))
    When xs ← local_intersect(t, r)
    Then xs.count = 2
      And xs[0].t = 2.75
      And xs[1].t = 3.25

  # Tangent to the outside of the tube: a double root, listed twice (as the book's cylinder
  # lists a tangent ray's).
  @chapter20
  Scenario: A ray tangent to the tube touches it at one t
    Given t ← torus()
      And r ← ray(point(1.25, 3, 0), vector(0, -1, 0))
    When xs ← local_intersect(t, r)
    Then xs.count = 2
      And xs[0].t = 3
      And xs[1].t = 3

  @chapter20
  Scenario: Radii change where a ray meets the torus
    Given t ← torus()
      And t.major_radius ← 2
      And t.minor_radius ← 0.5
      And r ← ray(point(-4, 0, 0), vector(1, 0, 0))
    When xs ← local_intersect(t, r)
    Then xs.count = 4
      And xs[0].t = 1.5
      And xs[1].t = 2.5
      And xs[2].t = 5.5
      And xs[3].t = 6.5

  # The normal points away from the tube's centre line.
  @chapter20
  Scenario Outline: The normal on a torus
    Given t ← torus()
    When n ← normal_at(t, <point>)
    Then n = <normal>

    Examples:
      | point                  | normal            |
      | point(1.25, 0, 0)      | vector(1, 0, 0)   |
      | point(0.75, 0, 0)      | vector(-1, 0, 0)  |
      | point(1, 0.25, 0)      | vector(0, 1, 0)   |
      | point(0, -0.25, 1)     | vector(0, -1, 0)  |
      | point(0, 0, -1.25)     | vector(0, 0, -1)  |

  @chapter20
  Scenario: The normal on a transformed torus
    Given t ← torus()
      And set_transform(t, translation(0, 1, 0))
    When n ← normal_at(t, point(1.25, 1, 0))
    Then n = vector(1, 0, 0)

  @chapter20
  Scenario: A torus has a bounding box
    Given t ← torus()
    When box ← bounds_of(t)
    Then box.min = point(-1.25, -0.25, -1.25)
      And box.max = point(1.25, 0.25, 1.25)

  @chapter20
  Scenario: A torus's bounding box follows its radii
    Given t ← torus()
      And t.major_radius ← 3
      And t.minor_radius ← 1
    When box ← bounds_of(t)
    Then box.min = point(-4, -1, -4)
      And box.max = point(4, 1, 4)

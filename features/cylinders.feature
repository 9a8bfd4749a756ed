Feature: Cylinders
  The cylinder of radius 1 around the y axis: infinitely long by default, optionally cut off
  at a minimum and maximum y (exclusive), and optionally closed with flat caps.

  # Directions are normalized first: the t values below assume unit-length rays.
  @chapter13
  Scenario Outline: Rays that miss a cylinder
    Given cyl ← cylinder()
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    When xs ← local_intersect(cyl, r)
    Then xs.count = 0

    Examples:
      | origin          | direction       |
      | point(1, 0, 0)  | vector(0, 1, 0) |
      | point(0, 0, 0)  | vector(0, 1, 0) |
      | point(0, 0, -5) | vector(1, 1, 1) |

  # The first ray just touches the side (tangent); the last one comes in at an angle.
  @chapter13
  Scenario Outline: Rays that strike a cylinder
    Given cyl ← cylinder()
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    When xs ← local_intersect(cyl, r)
    Then xs.count = 2
      And xs[0].t = <t0>
      And xs[1].t = <t1>

    Examples:
      | origin            | direction         | t0      | t1      |
      | point(1, 0, -5)   | vector(0, 0, 1)   | 5       | 5       |
      | point(0, 0, -5)   | vector(0, 0, 1)   | 4       | 6       |
      | point(0.5, 0, -5) | vector(0.1, 1, 1) | 6.80798 | 7.08872 |

  @chapter13
  Scenario Outline: The normal on the side of a cylinder
    Given cyl ← cylinder()
    When n ← local_normal_at(cyl, <point>)
    Then n = <normal>

    Examples:
      | point           | normal           |
      | point(1, 0, 0)  | vector(1, 0, 0)  |
      | point(0, 5, -1) | vector(0, 0, -1) |
      | point(0, -2, 1) | vector(0, 0, 1)  |
      | point(-1, 1, 0) | vector(-1, 0, 0) |

  @chapter13
  Scenario: A new cylinder extends without limit in both directions
    Given cyl ← cylinder()
    Then cyl.minimum = -infinity
      And cyl.maximum = infinity

  # The unlabelled first column numbers the rows. The limits are exclusive, so rays at
  # exactly y = 1 or y = 2 miss.
  @chapter13
  Scenario Outline: Rays against a cylinder cut off at both ends
    Given cyl ← cylinder()
      And cyl.minimum ← 1
      And cyl.maximum ← 2
      And direction ← normalize(<direction>)
      And r ← ray(<point>, direction)
    When xs ← local_intersect(cyl, r)
    Then xs.count = <count>

    Examples:
      |   | point             | direction         | count |
      | 1 | point(0, 1.5, 0)  | vector(0.1, 1, 0) | 0     |
      | 2 | point(0, 3, -5)   | vector(0, 0, 1)   | 0     |
      | 3 | point(0, 0, -5)   | vector(0, 0, 1)   | 0     |
      | 4 | point(0, 2, -5)   | vector(0, 0, 1)   | 0     |
      | 5 | point(0, 1, -5)   | vector(0, 0, 1)   | 0     |
      | 6 | point(0, 1.5, -2) | vector(0, 0, 1)   | 2     |

  @chapter13
  Scenario: A new cylinder is open at both ends
    Given cyl ← cylinder()
    Then cyl.closed = false

  # Rows 3 and 5 are corner cases: the ray leaves through the side exactly where the side
  # meets a cap.
  @chapter13
  Scenario Outline: Rays against the caps of a closed cylinder
    Given cyl ← cylinder()
      And cyl.minimum ← 1
      And cyl.maximum ← 2
      And cyl.closed ← true
      And direction ← normalize(<direction>)
      And r ← ray(<point>, direction)
    When xs ← local_intersect(cyl, r)
    Then xs.count = <count>

    Examples:
      |   | point            | direction        | count |
      | 1 | point(0, 3, 0)   | vector(0, -1, 0) | 2     |
      | 2 | point(0, 3, -2)  | vector(0, -1, 2) | 2     |
      | 3 | point(0, 4, -2)  | vector(0, -1, 1) | 2     |
      | 4 | point(0, 0, -2)  | vector(0, 1, 2)  | 2     |
      | 5 | point(0, -1, -2) | vector(0, 1, 1)  | 2     |

  @chapter13
  Scenario Outline: The normal on the caps of a closed cylinder
    Given cyl ← cylinder()
      And cyl.minimum ← 1
      And cyl.maximum ← 2
      And cyl.closed ← true
    When n ← local_normal_at(cyl, <point>)
    Then n = <normal>

    Examples:
      | point            | normal           |
      | point(0, 1, 0)   | vector(0, -1, 0) |
      | point(0.5, 1, 0) | vector(0, -1, 0) |
      | point(0, 1, 0.5) | vector(0, -1, 0) |
      | point(0, 2, 0)   | vector(0, 1, 0)  |
      | point(0.5, 2, 0) | vector(0, 1, 0)  |
      | point(0, 2, 0.5) | vector(0, 1, 0)  |

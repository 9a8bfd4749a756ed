Feature: Cones
  The double-napped cone x² + z² = y² around the y axis, with the same minimum, maximum and
  closed settings as the cylinder.

  @chapter13
  Scenario Outline: Rays that strike a cone
    Given shape ← cone()
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    When xs ← local_intersect(shape, r)
    Then xs.count = 2
      And xs[0].t = <t0>
      And xs[1].t = <t1>

    Examples:
      | origin          | direction           | t0      | t1       |
      | point(0, 0, -5) | vector(0, 0, 1)     | 5       | 5        |
      | point(0, 0, -5) | vector(1, 1, 1)     | 8.66025 | 8.66025  |
      | point(1, 1, -5) | vector(-0.5, -1, 1) | 4.55006 | 49.44994 |

  # Parallel to one half of the cone the quadratic term vanishes, leaving one intersection
  # with the other half.
  @chapter13
  Scenario: A ray parallel to one half of a cone meets it once
    Given shape ← cone()
      And direction ← normalize(vector(0, 1, 1))
      And r ← ray(point(0, 0, -1), direction)
    When xs ← local_intersect(shape, r)
    Then xs.count = 1
      And xs[0].t = 0.35355

  @chapter13
  Scenario Outline: Rays against the caps of a closed cone
    Given shape ← cone()
      And shape.minimum ← -0.5
      And shape.maximum ← 0.5
      And shape.closed ← true
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    When xs ← local_intersect(shape, r)
    Then xs.count = <count>

    Examples:
      | origin             | direction       | count |
      | point(0, 0, -5)    | vector(0, 1, 0) | 0     |
      | point(0, 0, -0.25) | vector(0, 1, 1) | 2     |
      | point(0, 0, -0.25) | vector(0, 1, 0) | 4     |

  # local_normal_at() does not normalize: normal_at() does that afterwards. At the tip the
  # normal is the zero vector.
  @chapter13
  Scenario Outline: The normal on the side of a cone
    Given shape ← cone()
    When n ← local_normal_at(shape, <point>)
    Then n = <normal>

    Examples:
      | point            | normal            |
      | point(0, 0, 0)   | vector(0, 0, 0)   |
      | point(1, 1, 1)   | vector(1, -√2, 1) |
      | point(-1, -1, 0) | vector(-1, 1, 0)  |

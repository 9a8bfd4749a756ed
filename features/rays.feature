Feature: Rays
  A ray is a starting point and a direction; it can be followed for a distance t and moved
  with a transformation matrix.

  @chapter05
  Scenario: A ray keeps its origin and direction
    Given origin ← point(1, 2, 3)
      And direction ← vector(4, 5, 6)
    When r ← ray(origin, direction)
    Then r.origin = origin
      And r.direction = direction

  # position(r, t) = origin + direction * t; t may be negative (behind the origin).
  @chapter05
  Scenario: Following a ray for a given distance
    Given r ← ray(point(2, 3, 4), vector(1, 0, 0))
    Then position(r, 0) = point(2, 3, 4)
      And position(r, 1) = point(3, 3, 4)
      And position(r, -1) = point(1, 3, 4)
      And position(r, 2.5) = point(4.5, 3, 4)

  @chapter05
  Scenario: Translating a ray moves its origin only
    Given r ← ray(point(1, 2, 3), vector(0, 1, 0))
      And m ← translation(3, 4, 5)
    When r2 ← transform(r, m)
    Then r2.origin = point(4, 6, 8)
      And r2.direction = vector(0, 1, 0)

  # Scaling changes the length of the direction: it is deliberately not normalized again.
  @chapter05
  Scenario: Scaling a ray changes its origin and its direction
    Given r ← ray(point(1, 2, 3), vector(0, 1, 0))
      And m ← scaling(2, 3, 4)
    When r2 ← transform(r, m)
    Then r2.origin = point(2, 6, 12)
      And r2.direction = vector(0, 3, 0)

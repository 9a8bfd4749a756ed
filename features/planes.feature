Feature: Planes
  The xz plane (y = 0), infinite in both directions, tested in its own object space with
  local_intersect() and local_normal_at().

  @chapter09
  Scenario: A plane has the same normal at every point
    Given p ← plane()
    When n1 ← local_normal_at(p, point(0, 0, 0))
      And n2 ← local_normal_at(p, point(10, 0, -10))
      And n3 ← local_normal_at(p, point(-5, 0, 150))
    Then n1 = vector(0, 1, 0)
      And n2 = vector(0, 1, 0)
      And n3 = vector(0, 1, 0)

  @chapter09
  Scenario: A ray running parallel to the plane never meets it
    Given p ← plane()
      And r ← ray(point(0, 10, 0), vector(0, 0, 1))
    When xs ← local_intersect(p, r)
    Then xs is empty

  # A ray lying in the plane is counted as a miss: the plane has no thickness to see.
  @chapter09
  Scenario: A ray lying in the plane does not meet it
    Given p ← plane()
      And r ← ray(point(0, 0, 0), vector(0, 0, 1))
    When xs ← local_intersect(p, r)
    Then xs is empty

  @chapter09
  Scenario: A ray coming down onto the plane
    Given p ← plane()
      And r ← ray(point(0, 1, 0), vector(0, -1, 0))
    When xs ← local_intersect(p, r)
    Then xs.count = 1
      And xs[0].t = 1
      And xs[0].object = p

  @chapter09
  Scenario: A ray coming up onto the plane
    Given p ← plane()
      And r ← ray(point(0, -1, 0), vector(0, 1, 0))
    When xs ← local_intersect(p, r)
    Then xs.count = 1
      And xs[0].t = 1
      And xs[0].object = p

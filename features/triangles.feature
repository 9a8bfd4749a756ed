Feature: Triangles
  A flat triangle given by three points, with its two edge vectors and its normal worked out
  once when it is built; rays are tested against it with the Möller–Trumbore algorithm.

  # e1 = p2 - p1, e2 = p3 - p1, normal = normalize(cross(e2, e1)).
  @chapter15
  Scenario: A triangle keeps its corners, edges and normal
    Given p1 ← point(0, 1, 0)
      And p2 ← point(-1, 0, 0)
      And p3 ← point(1, 0, 0)
    When t ← triangle(p1, p2, p3)
    Then t.p1 = p1
      And t.p2 = p2
      And t.p3 = p3
      And t.e1 = vector(-1, -1, 0)
      And t.e2 = vector(1, -1, 0)
      And t.normal = vector(0, 0, -1)

  @chapter15
  Scenario: A triangle has the same normal at every point
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
    When n1 ← local_normal_at(t, point(0, 0.5, 0))
      And n2 ← local_normal_at(t, point(-0.5, 0.75, 0))
      And n3 ← local_normal_at(t, point(0.5, 0.25, 0))
    Then n1 = t.normal
      And n2 = t.normal
      And n3 = t.normal

  @chapter15
  Scenario: A ray running parallel to a triangle misses it
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
      And r ← ray(point(0, -1, -2), vector(0, 1, 0))
    When xs ← local_intersect(t, r)
    Then xs is empty

  @chapter15
  Scenario: A ray passing outside the edge from p1 to p3
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
      And r ← ray(point(1, 1, -2), vector(0, 0, 1))
    When xs ← local_intersect(t, r)
    Then xs is empty

  @chapter15
  Scenario: A ray passing outside the edge from p1 to p2
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
      And r ← ray(point(-1, 1, -2), vector(0, 0, 1))
    When xs ← local_intersect(t, r)
    Then xs is empty

  @chapter15
  Scenario: A ray passing outside the edge from p2 to p3
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
      And r ← ray(point(0, -1, -2), vector(0, 0, 1))
    When xs ← local_intersect(t, r)
    Then xs is empty

  # `t` names the triangle here, while xs[0].t is the distance of the intersection.
  @chapter15
  Scenario: A ray passing through a triangle
    Given t ← triangle(point(0, 1, 0), point(-1, 0, 0), point(1, 0, 0))
      And r ← ray(point(0, 0.5, -2), vector(0, 0, 1))
    When xs ← local_intersect(t, r)
    Then xs.count = 1
      And xs[0].t = 2

Feature: Shapes
  What every kind of shape shares: a transformation, a material, and the conversion of rays
  and normals between world space and the shape's own space. test_shape() is a stand-in
  shape that records the ray it was given (saved_ray).

  @chapter09
  Scenario: A new shape has no transformation
    Given s ← test_shape()
    Then s.transform = identity_matrix

  @chapter09
  Scenario: A shape's transformation can be replaced
    Given s ← test_shape()
    When set_transform(s, translation(2, 3, 4))
    Then s.transform = translation(2, 3, 4)

  @chapter09
  Scenario: A new shape has the default material
    Given s ← test_shape()
    When m ← s.material
    Then m = material()

  @chapter09
  Scenario: A shape's material can be replaced
    Given s ← test_shape()
      And m ← material()
      And m.ambient ← 1
    When s.material ← m
    Then s.material = m

  # intersect() hands local_intersect() the ray in object space: here shrunk by half.
  @chapter09
  Scenario: A scaled shape sees the ray in its own space
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← test_shape()
    When set_transform(s, scaling(2, 2, 2))
      And xs ← intersect(s, r)
    Then s.saved_ray.origin = point(0, 0, -2.5)
      And s.saved_ray.direction = vector(0, 0, 0.5)

  @chapter09
  Scenario: A moved shape sees the ray in its own space
    Given r ← ray(point(0, 0, -5), vector(0, 0, 1))
      And s ← test_shape()
    When set_transform(s, translation(5, 0, 0))
      And xs ← intersect(s, r)
    Then s.saved_ray.origin = point(-5, 0, -5)
      And s.saved_ray.direction = vector(0, 0, 1)

  @chapter09
  Scenario: The normal on a moved shape
    Given s ← test_shape()
    When set_transform(s, translation(0, 1, 0))
      And n ← normal_at(s, point(0, 1.70711, -0.70711))
    Then n = vector(0, 0.70711, -0.70711)

  @chapter09
  Scenario: The normal on a squashed and turned shape
    Given s ← test_shape()
      And m ← scaling(1, 0.5, 1) * rotation_z(π/5)
    When set_transform(s, m)
      And n ← normal_at(s, point(0, √2/2, -√2/2))
    Then n = vector(0, 0.97014, -0.24254)

  @chapter14
  Scenario: A new shape has no parent
    Given s ← test_shape()
    Then s.parent is nothing

  # The point passes through every group on the way down: first g1's inverse, then g2's,
  # then the sphere's own.
  @chapter14
  Scenario: A point in world space converted to the space of a nested child
    Given g1 ← group()
      And set_transform(g1, rotation_y(π/2))
      And g2 ← group()
      And set_transform(g2, scaling(2, 2, 2))
      And add_child(g1, g2)
      And s ← sphere()
      And set_transform(s, translation(5, 0, 0))
      And add_child(g2, s)
    When p ← world_to_object(s, point(-2, 0, -10))
    Then p = point(0, 0, -1)

  # The normal goes the other way, child to parent, normalized at every level.
  @chapter14
  Scenario: A normal on a nested child converted to world space
    Given g1 ← group()
      And set_transform(g1, rotation_y(π/2))
      And g2 ← group()
      And set_transform(g2, scaling(1, 2, 3))
      And add_child(g1, g2)
      And s ← sphere()
      And set_transform(s, translation(5, 0, 0))
      And add_child(g2, s)
    When n ← normal_to_world(s, vector(√3/3, √3/3, √3/3))
    Then n = vector(0.2857, 0.4286, -0.8571)

  @chapter14
  Scenario: The normal on a child shape inside nested groups
    Given g1 ← group()
      And set_transform(g1, rotation_y(π/2))
      And g2 ← group()
      And set_transform(g2, scaling(1, 2, 3))
      And add_child(g1, g2)
      And s ← sphere()
      And set_transform(s, translation(5, 0, 0))
      And add_child(g2, s)
    When n ← normal_at(s, point(1.7321, 1.1547, -5.5774))
    Then n = vector(0.2857, 0.4286, -0.8571)

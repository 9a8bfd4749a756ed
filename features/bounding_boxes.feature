Feature: Bounding boxes and hierarchies
  A bounding box is the axis-aligned box around a shape. A group or a CSG shape asks its
  children about a ray only when the ray meets its box, and divide() sorts the children of
  a big group into subgroups by where they lie, so that one missed box skips many shapes.
  (The book's online bonus chapter, numbered 17 here.)

  @chapter17
  Scenario: An empty bounding box
    Given box ← bounding_box(empty)
    Then box.min = point(infinity, infinity, infinity)
      And box.max = point(-infinity, -infinity, -infinity)

  @chapter17
  Scenario: A bounding box with volume
    Given box ← bounding_box(min=point(-2, 0, -1.5) max=point(4, 3, 0.5))
    Then box.min = point(-2, 0, -1.5)
      And box.max = point(4, 3, 0.5)

  # Boxes are values: add_point() gives a new box, and the statement rebinds box to it.
  @chapter17
  Scenario: Adding points to an empty bounding box
    Given box ← bounding_box(empty)
      And p1 ← point(3, -1, 2)
      And p2 ← point(-4, 5, 0)
    When add_point(box, p1)
      And add_point(box, p2)
    Then box.min = point(-4, -1, 0)
      And box.max = point(3, 5, 2)

  @chapter17
  Scenario: Adding a point already inside a box changes nothing
    Given box ← bounding_box(min=point(0, 0, 0) max=point(2, 2, 2))
      And p ← point(1, 0, 2)
    When p is added to box
    Then box.min = point(0, 0, 0)
      And box.max = point(2, 2, 2)

  @chapter17
  Scenario: Adding one bounding box to another
    Given box1 ← bounding_box(min=point(-3, 0, 1) max=point(2, 6, 4))
      And box2 ← bounding_box(min=point(1, -2, -5) max=point(8, 3, 2))
    When add_box(box1, box2)
    Then box1.min = point(-3, -2, -5)
      And box1.max = point(8, 6, 4)
      And box2.min = point(1, -2, -5)

  # Adding the empty box's two corners as points would make the box infinite.
  @chapter17
  Scenario: Adding an empty box changes nothing, and adding to one gives the other box
    Given box ← bounding_box(min=point(-1, -1, -1) max=point(1, 2, 3))
      And nothing_inside ← bounding_box(empty)
    When box2 ← add_box(box, nothing_inside)
      And box is added to nothing_inside
    Then box2.min = point(-1, -1, -1)
      And box2.max = point(1, 2, 3)
      And nothing_inside.min = point(-1, -1, -1)
      And nothing_inside.max = point(1, 2, 3)

  @chapter17
  Scenario Outline: A box contains the points inside it and on its surface
    Given box ← bounding_box(min=point(-1, 2, -3) max=point(4, 6, 0))
      And p ← <point>
    Then box_contains_point(box, p) is <result>

    Examples:
      | point               | result |
      | point(-1, 2, -3)    | true   |
      | point(4, 6, 0)      | true   |
      | point(1.5, 4, -1.5) | true   |
      | point(4, 2, -3)     | true   |
      | point(-1.5, 4, -1)  | false  |
      | point(5, 4, -1)     | false  |
      | point(0, 1, -1)     | false  |
      | point(0, 7, -1)     | false  |
      | point(0, 4, -4)     | false  |
      | point(0, 4, 0.5)    | false  |

  @chapter17
  Scenario Outline: A box contains the boxes that fit inside it
    Given box ← bounding_box(min=point(-1, 2, -3) max=point(4, 6, 0))
      And box2 ← bounding_box(min=<min> max=<max>)
    Then box_contains_box(box, box2) is <result>

    Examples:
      | min               | max            | result |
      | point(-1, 2, -3)  | point(4, 6, 0) | true   |
      | point(0, 3, -2)   | point(1, 4, -1)| true   |
      | point(-2, 3, -2)  | point(1, 4, -1)| false  |
      | point(0, 3, -2)   | point(5, 4, -1)| false  |
      | point(0, 1, -2)   | point(1, 7, -1)| false  |
      | point(-5, -5, -5) | point(5, 5, 5) | false  |

  # rotation_y(π/4) turns the cube's corners out to √2 from the y axis.
  @chapter17
  Scenario: Rotating a bounding box
    Given box ← bounding_box(min=point(-1, -1, -1) max=point(1, 1, 1))
      And m ← rotation_y(π / 4)
    When box2 ← transform(box, m)
    Then box2.min = point(-√2, -1, -√2)
      And box2.max = point(√2, 1, √2)

  # A negative scale swaps which corner is the least.
  @chapter17
  Scenario: Scaling and moving a bounding box
    Given box ← bounding_box(min=point(0, 0, 0) max=point(1, 2, 3))
    When box2 ← transform(box, translation(1, -1, 2) * scaling(2, 0.5, -1))
    Then box2.min = point(1, -1, -1)
      And box2.max = point(3, 0, 2)

  @chapter17
  Scenario: A sphere's bounding box
    Given shape ← sphere()
    When box ← bounds_of(shape)
    Then box.min = point(-1, -1, -1)
      And box.max = point(1, 1, 1)

  @chapter17
  Scenario: A plane's bounding box is infinite in x and z
    Given shape ← plane()
    When box ← bounds_of(shape)
    Then box.min = point(-infinity, 0, -infinity)
      And box.max = point(infinity, 0, infinity)

  @chapter17
  Scenario: A cube's bounding box
    Given shape ← cube()
    When box ← bounds_of(shape)
    Then box.min = point(-1, -1, -1)
      And box.max = point(1, 1, 1)

  @chapter17
  Scenario: An untruncated cylinder's bounding box is infinite along y
    Given shape ← cylinder()
    When box ← bounds_of(shape)
    Then box.min = point(-1, -infinity, -1)
      And box.max = point(1, infinity, 1)

  @chapter17
  Scenario: A truncated cylinder's bounding box
    Given shape ← cylinder()
      And shape.minimum ← -2
      And shape.maximum ← 5
    When box ← bounds_of(shape)
    Then box.min = point(-1, -2, -1)
      And box.max = point(1, 5, 1)

  @chapter17
  Scenario: An untruncated cone's bounding box is infinite everywhere
    Given shape ← cone()
    When box ← bounds_of(shape)
    Then box.min = point(-infinity, -infinity, -infinity)
      And box.max = point(infinity, infinity, infinity)

  # The radius at height y is |y|: the wider end, at y = -4, decides x and z.
  @chapter17
  Scenario: A truncated cone's bounding box
    Given shape ← cone()
      And shape.minimum ← -4
      And shape.maximum ← 2
    When box ← bounds_of(shape)
    Then box.min = point(-4, -4, -4)
      And box.max = point(4, 2, 4)

  @chapter17
  Scenario: A triangle's bounding box
    Given shape ← triangle(point(-2, 5, 1), point(3, -1, 0), point(1, 2, -4))
    When box ← bounds_of(shape)
    Then box.min = point(-2, -1, -4)
      And box.max = point(3, 5, 1)

  @chapter17
  Scenario: A smooth triangle's bounding box is its corners'
    Given n ← vector(0, 1, 0)
      And shape ← smooth_triangle(point(0, 1, 0), point(-1, 0, 2), point(1, 0, 3), n, n, n)
    When box ← bounds_of(shape)
    Then box.min = point(-1, 0, 0)
      And box.max = point(1, 1, 3)

  @chapter17
  Scenario: The test shape's bounding box is the unit cube's
    Given shape ← test_shape()
    When box ← bounds_of(shape)
    Then box.min = point(-1, -1, -1)
      And box.max = point(1, 1, 1)

  @chapter17
  Scenario: A shape's bounding box in its parent's space
    Given shape ← cube()
      And set_transform(shape, translation(2, 0, -1) * scaling(1, 3, 0.5))
    When box ← parent_space_bounds_of(shape)
    Then box.min = point(1, -3, -1.5)
      And box.max = point(3, 3, -0.5)

  @chapter17
  Scenario: A plane's bounding box stays infinite in its parent's space
    Given shape ← plane()
      And set_transform(shape, translation(0, 2, 0) * scaling(3, 1, 3))
    When box ← parent_space_bounds_of(shape)
    Then box.min = point(-infinity, 2, -infinity)
      And box.max = point(infinity, 2, infinity)

  # The sphere reaches from (1, -2, -2) to (5, 2, 2), the cylinder from (-3, -1, 0) to (-1, 3, 2).
  @chapter17
  Scenario: A group's bounding box contains its children's
    Given s ← sphere()
      And set_transform(s, translation(3, 0, 0) * scaling(2, 2, 2))
      And c ← cylinder()
      And c.minimum ← 0
      And c.maximum ← 4
      And set_transform(c, translation(-2, -1, 1))
      And g ← group()
      And add_child(g, s)
      And add_child(g, c)
    When box ← bounds_of(g)
      And set_transform(g, translation(0, 10, 0))
      And box2 ← parent_space_bounds_of(g)
    Then box.min = point(-3, -2, -2)
      And box.max = point(5, 3, 2)
      And box2.min = point(-3, 8, -2)
      And box2.max = point(5, 13, 2)

  @chapter17
  Scenario: An empty group's bounding box is empty
    Given g ← group()
    When box ← bounds_of(g)
    Then box.min = point(infinity, infinity, infinity)
      And box.max = point(-infinity, -infinity, -infinity)

  # Whatever the operation, the box holds both operands.
  @chapter17
  Scenario: A CSG shape's bounding box contains both operands
    Given left ← sphere()
      And right ← cube()
      And set_transform(right, translation(2, 3, -4))
      And shape ← csg("difference", left, right)
    When box ← bounds_of(shape)
    Then box.min = point(-1, -1, -5)
      And box.max = point(3, 4, 1)

  @chapter17
  Scenario Outline: A ray and a box around the origin
    Given box ← bounding_box(min=point(-1, -1, -1) max=point(1, 1, 1))
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    Then intersects(box, r) is <result>

    Examples:
      | origin              | direction        | result |
      | point(-5, 0.5, 0)   | vector(1, 0, 0)  | true   |
      | point(0.5, 5, -0.5) | vector(0, -1, 0) | true   |
      | point(0, 0, 0)      | vector(1, 1, 1)  | true   |
      | point(-4, -3, 0)    | vector(4, 3, 0)  | true   |
      | point(-2, 0, 2)     | vector(2, 0, -1) | true   |
      | point(1, 0, 0)      | vector(0, 1, 0)  | true   |
      | point(0, 0, 5)      | vector(0, 0, 1)  | true   |
      | point(-3, 2, 0)     | vector(1, 0, 0)  | false  |
      | point(2, 2, 2)      | vector(1, 0, 0)  | false  |
      | point(3, 0, 0)      | vector(0, 1, 0)  | false  |
      | point(2, 0, 2)      | vector(-1, 0, 1) | false  |
      | point(0, 3, -3)     | vector(0, 0, 1)  | false  |

  # The last but one row: the box is behind the ray's origin, and still counts (as in the book).
  @chapter17
  Scenario Outline: A ray and a box that is not a cube
    Given box ← bounding_box(min=point(2, -1, 3) max=point(6, 1, 10))
      And direction ← normalize(<direction>)
      And r ← ray(<origin>, direction)
    Then intersects(box, r) is <result>

    Examples:
      | origin          | direction        | result |
      | point(0, 0, 5)  | vector(1, 0, 0)  | true   |
      | point(4, 5, 4)  | vector(0, -1, 0) | true   |
      | point(5, 0, 0)  | vector(0, 0, 1)  | true   |
      | point(4, 0, 6)  | vector(1, 1, 1)  | true   |
      | point(0, 0, 0)  | vector(1, 0, 1)  | true   |
      | point(4, 0, 12) | vector(0, 0, 1)  | true   |
      | point(0, 2, 5)  | vector(1, 0, 0)  | false  |
      | point(0, 0, 0)  | vector(1, 0, 6)  | false  |
      | point(8, 0, 5)  | vector(0, 0, -1) | false  |

  # A direction along an infinite extent, or one of exactly zero, needs no special case.
  @chapter17
  Scenario Outline: A ray and an infinite box
    Given box ← bounding_box(min=point(-infinity, 0, -infinity) max=point(infinity, 0, infinity))
      And r ← ray(<origin>, <direction>)
    Then intersects(box, r) is <result>

    Examples:
      | origin          | direction        | result |
      | point(0, 5, 0)  | vector(0, -1, 0) | true   |
      | point(7, 5, -9) | vector(1, -1, 0) | true   |
      | point(3, 0, -7) | vector(1, 0, 1)  | true   |
      | point(0, 5, 0)  | vector(1, 0, 0)  | false  |

  @chapter17
  Scenario: No ray meets the empty box
    Given box ← bounding_box(empty)
      And r ← ray(point(0, 0, 0), vector(0, 0, 1))
    Then intersects(box, r) is false

  @chapter17
  Scenario: A group does not ask its children about a ray that misses its box
    Given child ← test_shape()
      And set_transform(child, translation(3, 0, 0))
      And shape ← group()
      And add_child(shape, child)
      And r ← ray(point(0, 0, -5), vector(0, 0, 1))
    When xs ← intersect(shape, r)
    Then child.saved_ray is nothing

  @chapter17
  Scenario: A group asks its children about a ray that meets its box
    Given child ← test_shape()
      And set_transform(child, translation(3, 0, 0))
      And shape ← group()
      And add_child(shape, child)
      And r ← ray(point(3, 0, -5), vector(0, 0, 1))
    When xs ← intersect(shape, r)
    Then child.saved_ray.origin = point(0, 0, -5)

  @chapter17
  Scenario: A CSG shape does not ask its operands about a ray that misses its box
    Given left ← test_shape()
      And right ← test_shape()
      And set_transform(right, translation(0, 3, 0))
      And shape ← csg("union", left, right)
      And r ← ray(point(5, 0, -5), vector(0, 0, 1))
    When xs ← intersect(shape, r)
    Then left.saved_ray is nothing
      And right.saved_ray is nothing

  @chapter17
  Scenario: A CSG shape asks both operands about a ray that meets its box
    Given left ← test_shape()
      And right ← test_shape()
      And set_transform(right, translation(0, 3, 0))
      And shape ← csg("union", left, right)
      And r ← ray(point(0, 3, -5), vector(0, 0, 1))
    When xs ← intersect(shape, r)
    Then left.saved_ray.origin = point(0, 3, -5)
      And right.saved_ray.origin = point(0, 0, -5)

  # The box must follow changes made after add_child(): a kept box would miss the ray.
  @chapter17
  Scenario: A group's box follows a child that moves after it was added
    Given s ← sphere()
      And g ← group()
      And add_child(g, s)
      And r ← ray(point(5, 0, -5), vector(0, 0, 1))
    When xs1 ← intersect(g, r)
      And set_transform(s, translation(5, 0, 0))
      And xs2 ← intersect(g, r)
    Then xs1.count = 0
      And xs2.count = 2

  @chapter17
  Scenario: A group's box follows a child added, or lengthened, after a ray was cast
    Given c ← cylinder()
      And c.maximum ← 1
      And g ← group()
      And r ← ray(point(0, 5, -5), vector(0, 0, 1))
    When xs1 ← intersect(g, r)
      And add_child(g, c)
      And xs2 ← intersect(g, r)
      And c.maximum ← 6
      And xs3 ← intersect(g, r)
    Then xs1.count = 0
      And xs2.count = 0
      And xs3.count = 2

  @chapter17
  Scenario: Splitting a box with three equal sides cuts it across x
    Given box ← bounding_box(min=point(-2, -2, -2) max=point(4, 4, 4))
    When (left, right) ← split_bounds(box)
    Then left.min = point(-2, -2, -2)
      And left.max = point(1, 4, 4)
      And right.min = point(1, -2, -2)
      And right.max = point(4, 4, 4)

  @chapter17
  Scenario Outline: Splitting a box cuts its longest side in half
    Given box ← bounding_box(min=<min> max=<max>)
    When (left, right) ← split_bounds(box)
    Then left.min = <min>
      And left.max = <left_max>
      And right.min = <right_min>
      And right.max = <max>

    Examples:
      | min               | max            | left_max        | right_min         |
      | point(0, 0, 0)    | point(10, 2, 3)| point(5, 2, 3)  | point(5, 0, 0)    |
      | point(-1, -6, 0)  | point(1, 2, 3) | point(1, -2, 3) | point(-1, -2, 0)  |
      | point(0, 0, -10)  | point(2, 3, 2) | point(2, 3, -4) | point(0, 0, -4)   |

  # An infinite side has no middle: it is cut at 0 (or at its finite end).
  @chapter17
  Scenario: Splitting an infinite box cuts it at zero
    Given box ← bounding_box(min=point(-infinity, 0, -infinity) max=point(infinity, 1, infinity))
    When (left, right) ← split_bounds(box)
    Then left.max = point(0, 1, infinity)
      And right.min = point(0, 0, -infinity)

  # The big sphere s3 straddles the cut at x = 0, so it stays in g.
  @chapter17
  Scenario: Partitioning a group's children
    Given s1 ← sphere() with:
        | transform | translation(-3, 0, 0) |
      And s2 ← sphere() with:
        | transform | translation(3, 0, 0) |
      And s3 ← sphere() with:
        | transform | scaling(2, 2, 2) |
      And g ← group()
      And add_child(g, s1)
      And add_child(g, s2)
      And add_child(g, s3)
    When (left, right) ← partition_children(g)
    Then g.children = [s3]
      And left = [s1]
      And right = [s2]

  @chapter17
  Scenario: Making a subgroup from a list of shapes
    Given s1 ← sphere()
      And s2 ← cube()
      And g ← group()
    When make_subgroup(g, [s1, s2])
      And sub ← first child of g
    Then g.children.count = 1
      And sub.children = [s1, s2]
      And s1.parent = sub
      And sub.parent = g

  @chapter17
  Scenario: A subgroup takes its shapes out of the group
    Given s1 ← sphere()
      And s2 ← sphere()
      And s3 ← sphere()
      And g ← group()
      And add_child(g, s1)
      And add_child(g, s2)
      And add_child(g, s3)
    When make_subgroup(g, [s1, s3])
      And sub ← second child of g
    Then g.children.count = 2
      And first child of g = s2
      And sub.children = [s1, s3]

  @chapter17
  Scenario: Dividing a primitive changes nothing
    Given shape ← sphere()
    When divide(shape, 1)
    Then shape = sphere()

  # g's box is cut across x at 0: s1 and s2 go left, s3 straddles; then the left subgroup
  # is cut across y, its longest side, into one group for each sphere.
  @chapter17
  Scenario: Dividing a group partitions its children
    Given s1 ← sphere() with:
        | transform | translation(-4, -2, 0) |
      And s2 ← sphere() with:
        | transform | translation(-4, 2, 0) |
      And s3 ← sphere() with:
        | transform | scaling(5, 5, 5) |
      And g ← group()
      And add_child(g, s1)
      And add_child(g, s2)
      And add_child(g, s3)
    When divide(g, 1)
      And sub ← second child of g
      And a ← first child of sub
      And b ← second child of sub
    Then g.children.count = 2
      And first child of g = s3
      And sub.children.count = 2
      And a.children = [s1]
      And b.children = [s2]

  @chapter17
  Scenario: A group with fewer children than the threshold is not divided
    Given s1 ← sphere() with:
        | transform | translation(-2, 0, 0) |
      And s2 ← sphere() with:
        | transform | translation(2, 1, 0) |
      And s3 ← sphere() with:
        | transform | translation(2, -1, 0) |
      And g ← group()
      And add_child(g, s1)
      And add_child(g, s2)
      And add_child(g, s3)
    When divide(g, 4)
    Then g.children = [s1, s2, s3]

  # g has two children, too few to divide; the subgroup inside it has three.
  @chapter17
  Scenario: Dividing a group divides the groups inside it
    Given s1 ← sphere() with:
        | transform | translation(-2, 0, 0) |
      And s2 ← sphere() with:
        | transform | translation(2, 1, 0) |
      And s3 ← sphere() with:
        | transform | translation(2, -1, 0) |
      And sub ← group()
      And add_child(sub, s1)
      And add_child(sub, s2)
      And add_child(sub, s3)
      And s4 ← sphere()
      And g ← group()
      And add_child(g, sub)
      And add_child(g, s4)
    When divide(g, 3)
      And a ← first child of sub
      And b ← second child of sub
    Then g.children = [sub, s4]
      And sub.children.count = 2
      And a.children = [s1]
      And b.children = [s2, s3]

  @chapter17
  Scenario: Dividing a CSG shape divides both operands
    Given s1 ← sphere() with:
        | transform | translation(-1.5, 0, 0) |
      And s2 ← sphere() with:
        | transform | translation(1.5, 0, 0) |
      And left ← group()
      And add_child(left, s1)
      And add_child(left, s2)
      And s3 ← sphere() with:
        | transform | translation(0, 0, -1.5) |
      And s4 ← sphere() with:
        | transform | translation(0, 0, 1.5) |
      And right ← group()
      And add_child(right, s3)
      And add_child(right, s4)
      And shape ← csg("difference", left, right)
    When divide(shape, 1)
      And left1 ← first child of left
      And left2 ← second child of left
      And right1 ← first child of right
      And right2 ← second child of right
    Then left1.children = [s1]
      And left2.children = [s2]
      And right1.children = [s3]
      And right2.children = [s4]

  # Subgroups change how many boxes a ray meets, never what it hits.
  @chapter17
  Scenario: Dividing a group does not change its intersections
    Given s1 ← sphere() with:
        | transform | translation(-3, 0, -3) |
      And s2 ← cube() with:
        | transform | translation(3, 0, 2) |
      And s3 ← sphere() with:
        | transform | translation(0, 0, 6) |
      And g ← group()
      And add_child(g, s1)
      And add_child(g, s2)
      And add_child(g, s3)
      And r ← ray(point(-6, 0, -6), normalize(vector(1, 0, 1)))
    When xs1 ← intersect(g, r)
      And divide(g, 1)
      And xs2 ← intersect(g, r)
    Then xs1.count = 4
      And xs2 = xs1

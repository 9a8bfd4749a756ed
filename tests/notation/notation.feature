Feature: The book's notation, form by form
  Every form of the notation that the step library reads (docs/architecture.md), each shown
  at work in a small scenario. The project's own features use most of them; this file makes
  sure the rest keep working too.

  Background:
    Given black ← color(0, 0, 0)
      And white ← color(1, 1, 1)

  @chapter01
  Scenario: Square roots of numbers, names and parenthesized sums
    Given half ← √2/2
      And nine ← 9
    Then half = 0.70711
      And -√3/3 = -0.57735
      And √nine = 3
      And √(nine + 7) = 4
      And magnitude(vector(√3, 0, 1)) = 2

  @chapter01
  Scenario: π and the words for true, false and infinity
    Given far ← infinity
      And near ← -infinity
    Then π / 2 = 1.5708
      And far > 1000000
      And near < -1000000
      And far = infinity
      And true is true
      And false is false

  @chapter01
  Scenario: Every comparison the Then steps understand
    Given p ← point(1, 2, 3)
    Then p.x < p.y
      And p.z > p.y
      And p.x <= 1.00001
      And p.x <= 2
      And p.z >= 3
      And p != point(1, 2, 3.001)
      And p = approximately point(1.00001, 2, 3)
      And p is a point
      And p is not a vector
      And p - point(1, 2, 3) is a vector

  @chapter03
  Scenario: Matrix tables, indexing and size
    Given the following matrix A:
      | 1  | 2  |
      | 2  | 4  |
      And the following 4x4 matrix B:
      | 1 | 0 | 0 | √4 |
      | 0 | 1 | 0 | 0  |
      | 0 | 0 | 1 | 0  |
      | 0 | 0 | 0 | 1  |
    Then A.size = 2
      And A[1,1] = 4
      And A is not invertible
      And B is invertible
      And B * identity_matrix is the following matrix:
      | 1 | 0 | 0 | 2 |
      | 0 | 1 | 0 | 0 |
      | 0 | 0 | 1 | 0 |
      | 0 | 0 | 0 | 1 |
      And B = translation(2, 0, 0)

  @chapter04
  Scenario Outline: Outline values arrive in the step text
    Given r ← rotation_x(<angle>)
    Then r * point(0, 1, 0) = <expected>

    Examples:
      | angle | expected             |
      | π/4   | point(0, √2/2, √2/2) |
      | π/2   | point(0, 0, 1)       |

  @chapter05
  Scenario: t:object pairs, counts and an intersection equal to a number
    Given s ← sphere()
      And xs ← intersections(√2:s, -√2/2:s, 3:s)
    Then xs.count = 3
      And xs[0] = -√2/2
      And xs[1].t = 1.41421
      And xs[2].object = s
      And xs is not empty

  @chapter05
  Scenario: Nothing and an empty list
    Given xs ← intersections()
    Then hit(xs) is nothing
      And xs is empty
      And xs.count = 0

  @chapter06
  Scenario: lighting() without the object, as before chapter 10
    Given m ← material()
      And s ← sphere()
      And position ← point(0, 0, 0)
      And eyev ← vector(0, 0, -1)
      And normalv ← vector(0, 0, -1)
      And light ← point_light(point(0, 0, -10), color(1, 1, 1))
    When older ← lighting(m, light, position, eyev, normalv, true)
      And newer ← lighting(m, s, light, position, eyev, normalv, true)
    Then older = newer
      And older = color(0.1, 0.1, 0.1)

  @chapter06
  Scenario: Setting a field of a value rebinds the name
    Given m ← material()
    When m.ambient ← 0.25
      And m.color ← color(1, 0.5, 0)
    Then m.ambient = 0.25
      And m.color = color(1, 0.5, 0)

  @chapter05
  Scenario: In call position the function wins over a variable of the same name
    Given position ← point(7, 7, 7)
      And color ← white
      And r ← ray(point(2, 3, 4), vector(1, 0, 0))
    Then position(r, 1) = point(3, 3, 4)
      And color = color(1, 1, 1)
      And position = point(7, 7, 7)

  @chapter07
  Scenario: A world built step by step
    Given w ← world()
    Then w contains no objects
      And w has no light source
    Given s ← sphere() with:
      | material.color   | (0.8, 1.0, 0.6)        |
      | material.diffuse | 0.7                    |
      | transform        | scaling(0.5, 0.5, 0.5) |
    When s is added to w
      And w.light ← point_light(point(-10, 10, -10), white)
    Then w contains s
      And w.light = point_light(point(-10, 10, -10), color(1, 1, 1))
      And s.material.color = color(0.8, 1.0, 0.6)

  @chapter07
  Scenario: Changing a material through the first object in the world
    Given w ← default_world()
      And outer ← the first object in w
      And inner ← the second object in w
    When outer.material.ambient ← 1
      And inner has:
        | material.ambient | 0.5 |
    Then outer.material.ambient = 1
      And the first object in w = outer
      And inner.material.ambient = 0.5

  @chapter07
  Scenario: A keyword as a name, and a field of a frozen camera
    Given from ← point(0, 0, 8)
      And to ← point(0, 0, 0)
      And up ← vector(0, 1, 0)
      And c ← camera(160, 120, π/2)
    When c.transform ← view_transform(from, to, up)
    Then c.transform = translation(0, 0, -8)
      And c.hsize = 160
      And from = point(0, 0, 8)

  @chapter02
  Scenario: Painting and reading every pixel
    Given c ← canvas(4, 2)
    When every pixel of c is set to color(0.5, 0.25, 1)
    Then every pixel of c is color(0.5, 0.25, 1)
    When ppm ← canvas_to_ppm(c)
    Then lines 1-2 of ppm are
      """
      P3
      4 2
      """
      And ppm ends with a newline character

  @chapter11
  Scenario: A computation that must come to an end
    Given w ← world()
      And w.light ← point_light(point(0, 0, 0), white)
      And mirror ← plane() with:
        | material.reflective | 1 |
        | transform           | translation(0, -1, 0) |
      And mirror is added to w
    Then color_at(w, ray(point(0, 0, 0), vector(0, 1, 0))) should terminate successfully

  @chapter14
  Scenario: Children of a group by position
    Given g ← group()
      And s1 ← sphere()
      And s2 ← sphere() with:
        | transform | translation(5, 0, 0) |
    When add_child(g, s1)
      And add_child(g, s2)
      And c1 ← first child of g
      And c2 ← the second child of g
    Then g is not empty
      And g includes s2
      And c1 = s1
      And c2.transform = translation(5, 0, 0)
      And s1.parent = g

  @chapter15
  Scenario: OBJ text given inline, with a named group
    Given text ← a file containing:
      """
      a line the parser cannot read
      v -1 1 0
      v -1 0 0
      v 1 0 0
      v 1 1 0
      g Roof
      f 1 2 3
      f 1 3 4
      """
    When parser ← parse_obj_file(text)
      And roof ← "Roof" from parser
      And t2 ← second child of roof
    Then parser should have ignored 1 line
      And parser.vertices[4] = point(1, 1, 0)
      And t2.p1 = parser.vertices[1]
      And t2.p3 = parser.vertices[4]

  @chapter15
  Scenario: OBJ text read from a file beside the feature
    Given text ← the file "square.obj"
    When parser ← parse_obj_file(text)
      And g ← obj_to_group(parser)
    Then g includes "Square" from parser
      And parser.vertices[3] = point(1, 1, 0)

Feature: Tuples, points, vectors and colours
  The basic values of the tracer: four-component tuples (points have w = 1, vectors w = 0),
  the arithmetic on them, and colours as red/green/blue triples.

  @chapter01
  Scenario: A tuple whose w is 1 counts as a point
    Given a ← tuple(4.3, -4.2, 3.1, 1.0)
    Then a.x = 4.3
      And a.y = -4.2
      And a.z = 3.1
      And a.w = 1.0
      And a is a point
      And a is not a vector

  @chapter01
  Scenario: A tuple whose w is 0 counts as a vector
    Given a ← tuple(4.3, -4.2, 3.1, 0.0)
    Then a.x = 4.3
      And a.y = -4.2
      And a.z = 3.1
      And a.w = 0.0
      And a is not a point
      And a is a vector

  @chapter01
  Scenario: point() builds a tuple with w set to 1
    Given p ← point(4, -4, 3)
    Then p = tuple(4, -4, 3, 1)

  @chapter01
  Scenario: vector() builds a tuple with w set to 0
    Given v ← vector(4, -4, 3)
    Then v = tuple(4, -4, 3, 0)

  @chapter01
  Scenario: Tuples add component by component
    Given a1 ← tuple(3, -2, 5, 1)
      And a2 ← tuple(-2, 3, 1, 0)
    Then a1 + a2 = tuple(1, 1, 6, 1)

  @chapter01
  Scenario: The difference of two points is a vector
    Given p1 ← point(3, 2, 1)
      And p2 ← point(5, 6, 7)
    Then p1 - p2 = vector(-2, -4, -6)

  @chapter01
  Scenario: A point minus a vector is a point
    Given p ← point(3, 2, 1)
      And v ← vector(5, 6, 7)
    Then p - v = point(-2, -4, -6)

  @chapter01
  Scenario: The difference of two vectors is a vector
    Given v1 ← vector(3, 2, 1)
      And v2 ← vector(5, 6, 7)
    Then v1 - v2 = vector(-2, -4, -6)

  @chapter01
  Scenario: Taking a vector away from the zero vector flips it
    Given zero ← vector(0, 0, 0)
      And v ← vector(1, -2, 3)
    Then zero - v = vector(-1, 2, -3)

  # Unary minus negates all four components, w included.
  @chapter01
  Scenario: Negation flips the sign of every component
    Given a ← tuple(1, -2, 3, -4)
    Then -a = tuple(-1, 2, -3, 4)

  @chapter01
  Scenario: Scaling a tuple up by a number
    Given a ← tuple(1, -2, 3, -4)
    Then a * 3.5 = tuple(3.5, -7, 10.5, -14)

  @chapter01
  Scenario: Scaling a tuple down by a fraction
    Given a ← tuple(1, -2, 3, -4)
    Then a * 0.5 = tuple(0.5, -1, 1.5, -2)

  @chapter01
  Scenario: Dividing a tuple by a number
    Given a ← tuple(1, -2, 3, -4)
    Then a / 2 = tuple(0.5, -1, 1.5, -2)

  @chapter01
  Scenario: The length of the unit vector along x
    Given v ← vector(1, 0, 0)
    Then magnitude(v) = 1

  @chapter01
  Scenario: The length of the unit vector along y
    Given v ← vector(0, 1, 0)
    Then magnitude(v) = 1

  @chapter01
  Scenario: The length of the unit vector along z
    Given v ← vector(0, 0, 1)
    Then magnitude(v) = 1

  @chapter01
  Scenario: The length of a vector with positive components
    Given v ← vector(1, 2, 3)
    Then magnitude(v) = √14

  @chapter01
  Scenario: The length of a vector with negative components
    Given v ← vector(-1, -2, -3)
    Then magnitude(v) = √14

  @chapter01
  Scenario: Normalizing a vector along one axis
    Given v ← vector(4, 0, 0)
    Then normalize(v) = vector(1, 0, 0)

  # The exact answer is vector(1/√14, 2/√14, 3/√14).
  @chapter01
  Scenario: Normalizing a vector with three nonzero components
    Given v ← vector(1, 2, 3)
    Then normalize(v) = approximately vector(0.26726, 0.53452, 0.80178)

  @chapter01
  Scenario: A normalized vector has length one
    Given v ← vector(1, 2, 3)
    When norm ← normalize(v)
    Then magnitude(norm) = 1

  @chapter01
  Scenario: The dot product of two vectors is a number
    Given a ← vector(1, 2, 3)
      And b ← vector(2, 3, 4)
    Then dot(a, b) = 20

  # The cross product is not commutative: swapping the operands flips the result.
  @chapter01
  Scenario: The cross product of two vectors depends on their order
    Given a ← vector(1, 2, 3)
      And b ← vector(2, 3, 4)
    Then cross(a, b) = vector(-1, 2, -1)
      And cross(b, a) = vector(1, -2, 1)

  @chapter02
  Scenario: A colour has red, green and blue parts
    Given c ← color(-0.5, 0.4, 1.7)
    Then c.red = -0.5
      And c.green = 0.4
      And c.blue = 1.7

  @chapter02
  Scenario: Colours add channel by channel
    Given c1 ← color(0.9, 0.6, 0.75)
      And c2 ← color(0.7, 0.1, 0.25)
    Then c1 + c2 = color(1.6, 0.7, 1.0)

  @chapter02
  Scenario: Colours subtract channel by channel
    Given c1 ← color(0.9, 0.6, 0.75)
      And c2 ← color(0.7, 0.1, 0.25)
    Then c1 - c2 = color(0.2, 0.5, 0.5)

  @chapter02
  Scenario: Scaling a colour by a number
    Given c ← color(0.2, 0.3, 0.4)
    Then c * 2 = color(0.4, 0.6, 0.8)

  # Colour times colour multiplies matching channels (the Hadamard product).
  @chapter02
  Scenario: Multiplying two colours blends them
    Given c1 ← color(1, 0.2, 0.4)
      And c2 ← color(0.9, 1, 0.1)
    Then c1 * c2 = color(0.9, 0.2, 0.04)

  @chapter06
  Scenario: A vector hitting a flat surface at 45 degrees bounces off at 45 degrees
    Given v ← vector(1, -1, 0)
      And n ← vector(0, 1, 0)
    When r ← reflect(v, n)
    Then r = vector(1, 1, 0)

  @chapter06
  Scenario: A vector bouncing off a tilted surface
    Given v ← vector(0, -1, 0)
      And n ← vector(√2/2, √2/2, 0)
    When r ← reflect(v, n)
    Then r = vector(1, 0, 0)

Feature: Patterns
  Colours that vary over a surface: stripes, gradients, rings and checkers, each with a
  transformation of its own on top of the transformation of the object it decorates.

  Background:
    Given black ← color(0, 0, 0)
      And white ← color(1, 1, 1)

  @chapter10
  Scenario: A stripe pattern keeps its two colours
    Given pattern ← stripe_pattern(white, black)
    Then pattern.a = white
      And pattern.b = black

  @chapter10
  Scenario: Stripes do not change along y
    Given pattern ← stripe_pattern(white, black)
    Then stripe_at(pattern, point(0, 0, 0)) = white
      And stripe_at(pattern, point(0, 1, 0)) = white
      And stripe_at(pattern, point(0, 2, 0)) = white

  @chapter10
  Scenario: Stripes do not change along z
    Given pattern ← stripe_pattern(white, black)
    Then stripe_at(pattern, point(0, 0, 0)) = white
      And stripe_at(pattern, point(0, 0, 1)) = white
      And stripe_at(pattern, point(0, 0, 2)) = white

  # The colour depends on floor(x): even gives a, odd gives b, also for negative x.
  @chapter10
  Scenario: Stripes switch colour at every whole number of x
    Given pattern ← stripe_pattern(white, black)
    Then stripe_at(pattern, point(0, 0, 0)) = white
      And stripe_at(pattern, point(0.9, 0, 0)) = white
      And stripe_at(pattern, point(1, 0, 0)) = black
      And stripe_at(pattern, point(-0.1, 0, 0)) = black
      And stripe_at(pattern, point(-1, 0, 0)) = black
      And stripe_at(pattern, point(-1.1, 0, 0)) = white

  # `object` is just a variable name here.
  @chapter10
  Scenario: Scaling the object widens its stripes
    Given object ← sphere()
      And set_transform(object, scaling(2, 2, 2))
      And pattern ← stripe_pattern(white, black)
    When c ← stripe_at_object(pattern, object, point(1.5, 0, 0))
    Then c = white

  @chapter10
  Scenario: Scaling the pattern widens the stripes
    Given object ← sphere()
      And pattern ← stripe_pattern(white, black)
      And set_pattern_transform(pattern, scaling(2, 2, 2))
    When c ← stripe_at_object(pattern, object, point(1.5, 0, 0))
    Then c = white

  # The point goes from world space to object space, then on to pattern space.
  @chapter10
  Scenario: Stripes under both an object and a pattern transformation
    Given object ← sphere()
      And set_transform(object, scaling(2, 2, 2))
      And pattern ← stripe_pattern(white, black)
      And set_pattern_transform(pattern, translation(0.5, 0, 0))
    When c ← stripe_at_object(pattern, object, point(2.5, 0, 0))
    Then c = white

  @chapter10
  Scenario: A new pattern has no transformation
    Given pattern ← test_pattern()
    Then pattern.transform = identity_matrix

  @chapter10
  Scenario: A pattern's transformation can be replaced
    Given pattern ← test_pattern()
    When set_pattern_transform(pattern, translation(1, 2, 3))
    Then pattern.transform = translation(1, 2, 3)

  # test_pattern() returns the pattern-space point itself as a colour (x, y, z), which makes
  # the effect of the transformations visible.
  @chapter10
  Scenario: The object's transformation applies to any pattern
    Given shape ← sphere()
      And set_transform(shape, scaling(2, 2, 2))
      And pattern ← test_pattern()
    When c ← pattern_at_shape(pattern, shape, point(2, 3, 4))
    Then c = color(1, 1.5, 2)

  @chapter10
  Scenario: The pattern's own transformation applies to any pattern
    Given shape ← sphere()
      And pattern ← test_pattern()
      And set_pattern_transform(pattern, scaling(2, 2, 2))
    When c ← pattern_at_shape(pattern, shape, point(2, 3, 4))
    Then c = color(1, 1.5, 2)

  @chapter10
  Scenario: Object and pattern transformations together on any pattern
    Given shape ← sphere()
      And set_transform(shape, scaling(2, 2, 2))
      And pattern ← test_pattern()
      And set_pattern_transform(pattern, translation(0.5, 1, 1.5))
    When c ← pattern_at_shape(pattern, shape, point(2.5, 3, 3.5))
    Then c = color(0.75, 0.5, 0.25)

  @chapter10
  Scenario: A gradient blends evenly from one colour to the other along x
    Given pattern ← gradient_pattern(white, black)
    Then pattern_at(pattern, point(0, 0, 0)) = white
      And pattern_at(pattern, point(0.25, 0, 0)) = color(0.75, 0.75, 0.75)
      And pattern_at(pattern, point(0.5, 0, 0)) = color(0.5, 0.5, 0.5)
      And pattern_at(pattern, point(0.75, 0, 0)) = color(0.25, 0.25, 0.25)

  # 0.708 is a little more than √2/2, so that point is just past distance 1 from the y axis.
  @chapter10
  Scenario: Rings spread out in both x and z
    Given pattern ← ring_pattern(white, black)
    Then pattern_at(pattern, point(0, 0, 0)) = white
      And pattern_at(pattern, point(1, 0, 0)) = black
      And pattern_at(pattern, point(0, 0, 1)) = black
      And pattern_at(pattern, point(0.708, 0, 0.708)) = black

  @chapter10
  Scenario: Checkers alternate along x
    Given pattern ← checkers_pattern(white, black)
    Then pattern_at(pattern, point(0, 0, 0)) = white
      And pattern_at(pattern, point(0.99, 0, 0)) = white
      And pattern_at(pattern, point(1.01, 0, 0)) = black

  @chapter10
  Scenario: Checkers alternate along y
    Given pattern ← checkers_pattern(white, black)
    Then pattern_at(pattern, point(0, 0, 0)) = white
      And pattern_at(pattern, point(0, 0.99, 0)) = white
      And pattern_at(pattern, point(0, 1.01, 0)) = black

  @chapter10
  Scenario: Checkers alternate along z
    Given pattern ← checkers_pattern(white, black)
    Then pattern_at(pattern, point(0, 0, 0)) = white
      And pattern_at(pattern, point(0, 0, 0.99)) = white
      And pattern_at(pattern, point(0, 0, 1.01)) = black

Feature: Transformations
  The 4x4 matrices that move, scale, rotate and shear points and vectors, how they combine,
  and the view transformation that places the eye in a scene.

  # Here `transform` is an ordinary variable holding a matrix; chapter 5 also introduces a
  # function of that name, which the variable simply hides.
  @chapter04
  Scenario: A translation matrix moves a point
    Given transform ← translation(5, -3, 2)
      And p ← point(-3, 4, 5)
    Then transform * p = point(2, 1, 7)

  @chapter04
  Scenario: The inverse of a translation moves a point back
    Given transform ← translation(5, -3, 2)
      And inv ← inverse(transform)
      And p ← point(-3, 4, 5)
    Then inv * p = point(-8, 7, 3)

  # A vector has w = 0, so the translation column never reaches it.
  @chapter04
  Scenario: A translation leaves vectors alone
    Given transform ← translation(5, -3, 2)
      And v ← vector(-3, 4, 5)
    Then transform * v = v

  @chapter04
  Scenario: A scaling matrix stretches a point
    Given transform ← scaling(2, 3, 4)
      And p ← point(-4, 6, 8)
    Then transform * p = point(-8, 18, 32)

  @chapter04
  Scenario: A scaling matrix stretches a vector
    Given transform ← scaling(2, 3, 4)
      And v ← vector(-4, 6, 8)
    Then transform * v = vector(-8, 18, 32)

  @chapter04
  Scenario: The inverse of a scaling shrinks a vector
    Given transform ← scaling(2, 3, 4)
      And inv ← inverse(transform)
      And v ← vector(-4, 6, 8)
    Then inv * v = vector(-2, 2, 2)

  @chapter04
  Scenario: Scaling by a negative factor mirrors a point
    Given transform ← scaling(-1, 1, 1)
      And p ← point(2, 3, 4)
    Then transform * p = point(-2, 3, 4)

  # Angles are in radians; rotations follow the left-hand rule.
  @chapter04
  Scenario: Turning a point about the x axis
    Given p ← point(0, 1, 0)
      And half_quarter ← rotation_x(π / 4)
      And full_quarter ← rotation_x(π / 2)
    Then half_quarter * p = point(0, √2/2, √2/2)
      And full_quarter * p = point(0, 0, 1)

  @chapter04
  Scenario: The inverse of an x rotation turns the other way
    Given p ← point(0, 1, 0)
      And half_quarter ← rotation_x(π / 4)
      And inv ← inverse(half_quarter)
    Then inv * p = point(0, √2/2, -√2/2)

  @chapter04
  Scenario: Turning a point about the y axis
    Given p ← point(0, 0, 1)
      And half_quarter ← rotation_y(π / 4)
      And full_quarter ← rotation_y(π / 2)
    Then half_quarter * p = point(√2/2, 0, √2/2)
      And full_quarter * p = point(1, 0, 0)

  @chapter04
  Scenario: Turning a point about the z axis
    Given p ← point(0, 1, 0)
      And half_quarter ← rotation_z(π / 4)
      And full_quarter ← rotation_z(π / 2)
    Then half_quarter * p = point(-√2/2, √2/2, 0)
      And full_quarter * p = point(-1, 0, 0)

  # shearing(xy, xz, yx, yz, zx, zy): "xy" is how much x changes per unit of y, and so on.
  @chapter04
  Scenario: Shearing x by y
    Given transform ← shearing(1, 0, 0, 0, 0, 0)
      And p ← point(2, 3, 4)
    Then transform * p = point(5, 3, 4)

  @chapter04
  Scenario: Shearing x by z
    Given transform ← shearing(0, 1, 0, 0, 0, 0)
      And p ← point(2, 3, 4)
    Then transform * p = point(6, 3, 4)

  @chapter04
  Scenario: Shearing y by x
    Given transform ← shearing(0, 0, 1, 0, 0, 0)
      And p ← point(2, 3, 4)
    Then transform * p = point(2, 5, 4)

  @chapter04
  Scenario: Shearing y by z
    Given transform ← shearing(0, 0, 0, 1, 0, 0)
      And p ← point(2, 3, 4)
    Then transform * p = point(2, 7, 4)

  @chapter04
  Scenario: Shearing z by x
    Given transform ← shearing(0, 0, 0, 0, 1, 0)
      And p ← point(2, 3, 4)
    Then transform * p = point(2, 3, 6)

  @chapter04
  Scenario: Shearing z by y
    Given transform ← shearing(0, 0, 0, 0, 0, 1)
      And p ← point(2, 3, 4)
    Then transform * p = point(2, 3, 7)

  @chapter04
  Scenario: Transformations applied one after another
    Given p ← point(1, 0, 1)
      And A ← rotation_x(π / 2)
      And B ← scaling(5, 5, 5)
      And C ← translation(10, 5, 7)
    When p2 ← A * p
    Then p2 = point(1, -1, 0)
    When p3 ← B * p2
    Then p3 = point(5, -5, 0)
    When p4 ← C * p3
    Then p4 = point(15, 0, 7)

  # To rotate, then scale, then translate, the matrices are multiplied in the opposite order.
  @chapter04
  Scenario: A chain of transformations is multiplied in reverse order
    Given p ← point(1, 0, 1)
      And A ← rotation_x(π / 2)
      And B ← scaling(5, 5, 5)
      And C ← translation(10, 5, 7)
    When T ← C * B * A
    Then T * p = point(15, 0, 7)

  # `from` is a keyword in Python but just a variable name here.
  @chapter07
  Scenario: Looking down negative z from the origin needs no view transformation
    Given from ← point(0, 0, 0)
      And to ← point(0, 0, -1)
      And up ← vector(0, 1, 0)
    When t ← view_transform(from, to, up)
    Then t = identity_matrix

  @chapter07
  Scenario: Looking down positive z mirrors x and z
    Given from ← point(0, 0, 0)
      And to ← point(0, 0, 1)
      And up ← vector(0, 1, 0)
    When t ← view_transform(from, to, up)
    Then t = scaling(-1, 1, -1)

  # Moving the eye back is the same as moving the whole world forward.
  @chapter07
  Scenario: A view transformation moves the world rather than the eye
    Given from ← point(0, 0, 8)
      And to ← point(0, 0, 0)
      And up ← vector(0, 1, 0)
    When t ← view_transform(from, to, up)
    Then t = translation(0, 0, -8)

  @chapter07
  Scenario: A view transformation for an arbitrary eye, target and up vector
    Given from ← point(1, 3, 2)
      And to ← point(4, -2, 8)
      And up ← vector(1, 1, 0)
    When t ← view_transform(from, to, up)
    Then t is the following 4x4 matrix:
      | -0.50709 | 0.50709 |  0.67612 | -2.36643 |
      |  0.76772 | 0.60609 |  0.12122 | -2.82843 |
      | -0.35857 | 0.59761 | -0.71714 |  0.00000 |
      |  0.00000 | 0.00000 |  0.00000 |  1.00000 |

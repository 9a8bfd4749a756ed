Feature: Camera
  A camera maps a canvas of hsize x vsize pixels onto a view of the world one unit in front
  of the eye, casts a ray through each pixel and renders the image.

  @chapter07
  Scenario: A camera keeps its size and field of view
    Given hsize ← 160
      And vsize ← 120
      And field_of_view ← π/2
    When c ← camera(hsize, vsize, field_of_view)
    Then c.hsize = 160
      And c.vsize = 120
      And c.field_of_view = π/2
      And c.transform = identity_matrix

  @chapter07
  Scenario: The size of a pixel on a canvas wider than it is tall
    Given c ← camera(200, 125, π/2)
    Then c.pixel_size = 0.01

  @chapter07
  Scenario: The size of a pixel on a canvas taller than it is wide
    Given c ← camera(125, 200, π/2)
    Then c.pixel_size = 0.01

  # Rays go through the centre of a pixel, hence the odd canvas sizes.
  @chapter07
  Scenario: The ray through the middle pixel goes straight ahead
    Given c ← camera(201, 101, π/2)
    When r ← ray_for_pixel(c, 100, 50)
    Then r.origin = point(0, 0, 0)
      And r.direction = vector(0, 0, -1)

  @chapter07
  Scenario: The ray through the top-left pixel
    Given c ← camera(201, 101, π/2)
    When r ← ray_for_pixel(c, 0, 0)
    Then r.origin = point(0, 0, 0)
      And r.direction = vector(0.66519, 0.33259, -0.66851)

  # Setting c.transform gives the camera a new transformation (the step library builds an
  # updated camera).
  @chapter07
  Scenario: Moving and turning the camera moves and turns its rays
    Given c ← camera(201, 101, π/2)
    When c.transform ← rotation_y(π/4) * translation(0, -2, 5)
      And r ← ray_for_pixel(c, 100, 50)
    Then r.origin = point(0, 2, -5)
      And r.direction = vector(√2/2, 0, -√2/2)

  # The middle pixel looks straight at the default world's outer sphere.
  @chapter07
  Scenario: Rendering the default world through a camera
    Given w ← default_world()
      And c ← camera(11, 11, π/2)
      And from ← point(0, 0, -5)
      And to ← point(0, 0, 0)
      And up ← vector(0, 1, 0)
      And c.transform ← view_transform(from, to, up)
    When image ← render(c, w)
    Then pixel_at(image, 5, 5) = color(0.38066, 0.47583, 0.2855)

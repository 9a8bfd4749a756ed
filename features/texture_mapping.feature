Feature: Texture mapping
  A texture is a flat picture over the unit square, addressed by (u, v): u from left to
  right, v from bottom to top. A mapping turns a point on a shape into (u, v), so the flat
  picture wraps around a sphere, tiles a plane, rolls around a cylinder or covers the six
  faces of a cube. Images come from plain PPM text. (The book's online bonus chapter,
  numbered 19 here.)

  Background:
    Given black ← color(0, 0, 0)
      And white ← color(1, 1, 1)

  # ---------------------------------------------------------------- UV patterns

  @chapter19
  Scenario Outline: Checkers on the unit square alternate in u and in v
    Given checkers ← uv_checkers(2, 2, black, white)
    When c ← uv_pattern_at(checkers, <u>, <v>)
    Then c = <expected>

    Examples:
      | u   | v   | expected |
      | 0.0 | 0.0 | black    |
      | 0.5 | 0.0 | white    |
      | 0.0 | 0.5 | white    |
      | 0.5 | 0.5 | black    |
      | 1.0 | 1.0 | black    |

  # The corner patches show which way a mapping turns the square.
  @chapter19
  Scenario Outline: The align check has one patch of color in each corner
    Given main ← color(1, 1, 1)
      And ul ← color(1, 0, 0)
      And ur ← color(1, 1, 0)
      And bl ← color(0, 1, 0)
      And br ← color(0, 1, 1)
      And pattern ← uv_align_check(main, ul, ur, bl, br)
    When c ← uv_pattern_at(pattern, <u>, <v>)
    Then c = <expected>

    Examples:
      | u   | v   | expected |
      | 0.5 | 0.5 | main     |
      | 0.1 | 0.9 | ul       |
      | 0.9 | 0.9 | ur       |
      | 0.1 | 0.1 | bl       |
      | 0.9 | 0.1 | br       |
      | 0.5 | 0.9 | main     |
      | 0.1 | 0.5 | main     |

  # ---------------------------------------------------------------- mappings

  @chapter19
  Scenario Outline: A spherical map reads a point like longitude and latitude
    Given p ← <point>
    When (u, v) ← spherical_map(p)
    Then u = <u>
      And v = <v>

    Examples:
      | point                | u    | v    |
      | point(0, 0, -1)      | 0.0  | 0.5  |
      | point(1, 0, 0)       | 0.25 | 0.5  |
      | point(0, 0, 1)       | 0.5  | 0.5  |
      | point(-1, 0, 0)      | 0.75 | 0.5  |
      | point(0, 1, 0)       | 0.5  | 1.0  |
      | point(0, -1, 0)      | 0.5  | 0.0  |
      | point(√2/2, √2/2, 0) | 0.25 | 0.75 |

  @chapter19
  Scenario Outline: A planar map tiles the xz plane with unit squares
    Given p ← <point>
    When (u, v) ← planar_map(p)
    Then u = <u>
      And v = <v>

    Examples:
      | point                   | u    | v    |
      | point(0.25, 0, 0.5)     | 0.25 | 0.5  |
      | point(0.25, 0, -0.25)   | 0.25 | 0.75 |
      | point(0.25, 0.5, -0.25) | 0.25 | 0.75 |
      | point(1.25, 0, 0.5)     | 0.25 | 0.5  |
      | point(0.25, 0, -1.75)   | 0.25 | 0.25 |
      | point(1, 0, -1)         | 0.0  | 0.0  |
      | point(0, 0, 0)          | 0.0  | 0.0  |

  @chapter19
  Scenario Outline: A cylindrical map goes around the y axis and repeats every unit up
    Given p ← <point>
    When (u, v) ← cylindrical_map(p)
    Then u = <u>
      And v = <v>

    Examples:
      | point                          | u     | v    |
      | point(0, 0, -1)                | 0.0   | 0.0  |
      | point(0, 0.5, -1)              | 0.0   | 0.5  |
      | point(0, 1, -1)                | 0.0   | 0.0  |
      | point(0.70711, 0.5, -0.70711)  | 0.125 | 0.5  |
      | point(1, 0.5, 0)               | 0.25  | 0.5  |
      | point(0.70711, 0.5, 0.70711)   | 0.375 | 0.5  |
      | point(0, -0.25, 1)             | 0.5   | 0.75 |
      | point(-0.70711, 0.5, 0.70711)  | 0.625 | 0.5  |
      | point(-1, 1.25, 0)             | 0.75  | 0.25 |
      | point(-0.70711, 0.5, -0.70711) | 0.875 | 0.5  |

  # ---------------------------------------------------------------- texture_map

  @chapter19
  Scenario Outline: Checkers wrapped around a sphere by a texture map
    Given checkers ← uv_checkers(16, 8, black, white)
      And pattern ← texture_map(checkers, spherical_map)
    Then pattern_at(pattern, <point>) = <color>

    Examples:
      | point                            | color |
      | point(0.4315, 0.4670, 0.7719)    | white |
      | point(-0.9654, 0.2552, -0.0534)  | black |
      | point(0.1039, 0.7090, 0.6975)    | white |
      | point(-0.4986, -0.7856, -0.3663) | black |
      | point(-0.0317, -0.9395, 0.3411)  | black |
      | point(0.4809, -0.7721, 0.4154)   | black |
      | point(0.0285, -0.9612, -0.2745)  | black |
      | point(-0.5734, -0.2162, -0.7903) | white |
      | point(0.7688, -0.1470, 0.6223)   | black |
      | point(-0.7652, 0.2175, 0.6060)   | black |

  @chapter19
  Scenario: A texture map starts with the identity transform and takes another
    Given pattern ← texture_map(uv_checkers(2, 1, black, white), planar_map)
    Then pattern.transform = identity_matrix
    When set_pattern_transform(pattern, translation(1, 2, 3))
    Then pattern.transform = translation(1, 2, 3)

  # Two squares across u: the half of the sphere facing +x (u below 0.5) is black.
  @chapter19
  Scenario: A texture map sees a point through the shape's and the pattern's transforms
    Given s ← sphere()
      And set_transform(s, scaling(2, 2, 2))
      And pattern ← texture_map(uv_checkers(2, 1, black, white), spherical_map)
    Then pattern_at_shape(pattern, s, point(2, 0, 0)) = black
      And pattern_at_shape(pattern, s, point(-2, 0, 0)) = white
    When set_pattern_transform(pattern, rotation_y(π))
    Then pattern_at_shape(pattern, s, point(2, 0, 0)) = white
      And pattern_at_shape(pattern, s, point(-2, 0, 0)) = black

  @chapter19
  Scenario: A material lit with a texture map takes its color from the map
    Given m ← material()
      And m.pattern ← texture_map(uv_checkers(2, 2, black, white), planar_map)
      And m.ambient ← 1
      And m.diffuse ← 0
      And m.specular ← 0
      And s ← plane()
      And eyev ← vector(0, 1, 0)
      And normalv ← vector(0, 1, 0)
      And light ← point_light(point(0, 10, 0), color(1, 1, 1))
    When c1 ← lighting(m, s, light, point(0.25, 0, 0.25), eyev, normalv, false)
      And c2 ← lighting(m, s, light, point(0.75, 0, 0.25), eyev, normalv, false)
    Then c1 = color(0, 0, 0)
      And c2 = color(1, 1, 1)

  # ---------------------------------------------------------------- the cube

  @chapter19
  Scenario Outline: The face of the cube a point is on
    When face ← face_from_point(<point>)
    Then face = <face>

    Examples:
      | point                  | face    |
      | point(-1, 0.5, -0.25)  | "left"  |
      | point(1.1, -0.75, 0.8) | "right" |
      | point(0.1, 0.6, 0.9)   | "front" |
      | point(-0.7, 0, -2)     | "back"  |
      | point(0.5, 1, 0.9)     | "up"    |
      | point(-0.2, -1.3, 1.1) | "down"  |

  # A face may be written as a bare word too.
  @chapter19
  Scenario Outline: A corner or an edge belongs to the face of x first, then of y
    Then face_from_point(<point>) = <face>

    Examples:
      | point             | face  |
      | point(1, 1, 1)    | right |
      | point(-1, 1, -1)  | left  |
      | point(0.5, -1, 1) | down  |
      | point(0, 1, -1)   | up    |

  @chapter19
  Scenario Outline: The front face seen from +z
    When (u, v) ← cube_uv_front(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point               | u    | v    |
      | point(-0.5, 0.5, 1) | 0.25 | 0.75 |
      | point(0.5, -0.5, 1) | 0.75 | 0.25 |
      | point(0, 0, 1)      | 0.5  | 0.5  |

  @chapter19
  Scenario Outline: The back face seen from -z
    When (u, v) ← cube_uv_back(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point                 | u    | v    |
      | point(0.5, 0.5, -1)   | 0.25 | 0.75 |
      | point(-0.5, -0.5, -1) | 0.75 | 0.25 |
      | point(0, 0, -1)       | 0.5  | 0.5  |

  @chapter19
  Scenario Outline: The left face seen from -x
    When (u, v) ← cube_uv_left(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point                | u    | v    |
      | point(-1, 0.5, -0.5) | 0.25 | 0.75 |
      | point(-1, -0.5, 0.5) | 0.75 | 0.25 |
      | point(-1, 0, 0)      | 0.5  | 0.5  |

  @chapter19
  Scenario Outline: The right face seen from +x
    When (u, v) ← cube_uv_right(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point                | u    | v    |
      | point(1, 0.5, 0.5)   | 0.25 | 0.75 |
      | point(1, -0.5, -0.5) | 0.75 | 0.25 |
      | point(1, 0, 0)       | 0.5  | 0.5  |

  @chapter19
  Scenario Outline: The upper face seen from above
    When (u, v) ← cube_uv_up(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point                | u    | v    |
      | point(-0.5, 1, -0.5) | 0.25 | 0.75 |
      | point(0.5, 1, 0.5)   | 0.75 | 0.25 |
      | point(0, 1, 0)       | 0.5  | 0.5  |

  @chapter19
  Scenario Outline: The lower face seen from below
    When (u, v) ← cube_uv_down(<point>)
    Then u = <u>
      And v = <v>

    Examples:
      | point                | u    | v    |
      | point(-0.5, -1, 0.5) | 0.25 | 0.75 |
      | point(0.5, -1, -0.5) | 0.75 | 0.25 |
      | point(0, -1, 0)      | 0.5  | 0.5  |

  # Each face's corner patches meet the same colors on the neighbouring faces' corners.
  @chapter19
  Scenario Outline: A cube map gives each face its own pattern (<id>)
    Given red ← color(1, 0, 0)
      And yellow ← color(1, 1, 0)
      And brown ← color(1, 0.5, 0)
      And green ← color(0, 1, 0)
      And cyan ← color(0, 1, 1)
      And blue ← color(0, 0, 1)
      And purple ← color(1, 0, 1)
      And left ← uv_align_check(yellow, cyan, red, blue, brown)
      And front ← uv_align_check(cyan, red, yellow, brown, green)
      And right ← uv_align_check(red, yellow, purple, green, white)
      And back ← uv_align_check(green, purple, cyan, white, blue)
      And up ← uv_align_check(brown, cyan, purple, red, yellow)
      And down ← uv_align_check(purple, brown, green, blue, white)
      And pattern ← cube_map(left, front, right, back, up, down)
    Then pattern_at(pattern, <point>) = <color>

    Examples:
      | id | point                 | color  |
      | L1 | point(-1, 0, 0)       | yellow |
      | L2 | point(-1, 0.9, -0.9)  | cyan   |
      | L3 | point(-1, 0.9, 0.9)   | red    |
      | L4 | point(-1, -0.9, -0.9) | blue   |
      | L5 | point(-1, -0.9, 0.9)  | brown  |
      | F1 | point(0, 0, 1)        | cyan   |
      | F2 | point(-0.9, 0.9, 1)   | red    |
      | F3 | point(0.9, 0.9, 1)    | yellow |
      | F4 | point(-0.9, -0.9, 1)  | brown  |
      | F5 | point(0.9, -0.9, 1)   | green  |
      | R1 | point(1, 0, 0)        | red    |
      | R2 | point(1, 0.9, 0.9)    | yellow |
      | R3 | point(1, 0.9, -0.9)   | purple |
      | R4 | point(1, -0.9, 0.9)   | green  |
      | R5 | point(1, -0.9, -0.9)  | white  |
      | B1 | point(0, 0, -1)       | green  |
      | B2 | point(0.9, 0.9, -1)   | purple |
      | B3 | point(-0.9, 0.9, -1)  | cyan   |
      | B4 | point(0.9, -0.9, -1)  | white  |
      | B5 | point(-0.9, -0.9, -1) | blue   |
      | U1 | point(0, 1, 0)        | brown  |
      | U2 | point(-0.9, 1, -0.9)  | cyan   |
      | U3 | point(0.9, 1, -0.9)   | purple |
      | U4 | point(-0.9, 1, 0.9)   | red    |
      | U5 | point(0.9, 1, 0.9)    | yellow |
      | D1 | point(0, -1, 0)       | purple |
      | D2 | point(-0.9, -1, 0.9)  | brown  |
      | D3 | point(0.9, -1, 0.9)   | green  |
      | D4 | point(-0.9, -1, -0.9) | blue   |
      | D5 | point(0.9, -1, -0.9)  | white  |

  # The cube is scaled by 2, so the world point (-2, 1.8, 1.8) is (-1, 0.9, 0.9) on the cube.
  @chapter19
  Scenario: A cube map on a transformed cube
    Given red ← color(1, 0, 0)
      And plain ← uv_align_check(white, black, black, black, black)
      And left ← uv_align_check(white, black, red, black, black)
      And pattern ← cube_map(left, plain, plain, plain, plain, plain)
      And c ← cube()
      And set_transform(c, scaling(2, 2, 2))
    Then pattern_at_shape(pattern, c, point(-2, 1.8, 1.8)) = red
      And pattern_at_shape(pattern, c, point(-2, 1.8, -1.8)) = black
      And pattern_at_shape(pattern, c, point(-2, 0, 0)) = white

  # ---------------------------------------------------------------- PPM images

  @chapter19
  Scenario: A PPM text must start with the magic number P3
    Given ppm ← a file containing:
      """
      P32
      1 1
      255
      0 0 0
      """
    Then canvas_from_ppm(ppm) should fail

  @chapter19
  Scenario: The canvas read from a PPM text has the size in its header
    Given ppm ← a file containing:
      """
      P3
      10 2
      255
      0 0 0  0 0 0  0 0 0  0 0 0  0 0 0
      0 0 0  0 0 0  0 0 0  0 0 0  0 0 0
      0 0 0  0 0 0  0 0 0  0 0 0  0 0 0
      0 0 0  0 0 0  0 0 0  0 0 0  0 0 0
      """
    When image ← canvas_from_ppm(ppm)
    Then image.width = 10
      And image.height = 2

  @chapter19
  Scenario Outline: A PPM text's pixels come row by row from the top left
    Given ppm ← a file containing:
      """
      P3
      4 3
      255
      255 127 0  0 127 255  127 255 0  255 255 255
      0 0 0  255 0 0  0 255 0  0 0 255
      255 255 0  0 255 255  255 0 255  127 127 127
      """
    When image ← canvas_from_ppm(ppm)
    Then pixel_at(image, <x>, <y>) = <color>

    Examples:
      | x | y | color                            |
      | 0 | 0 | color(1, 0.49804, 0)             |
      | 1 | 0 | color(0, 0.49804, 1)             |
      | 2 | 0 | color(0.49804, 1, 0)             |
      | 3 | 0 | color(1, 1, 1)                   |
      | 0 | 1 | color(0, 0, 0)                   |
      | 1 | 1 | color(1, 0, 0)                   |
      | 2 | 1 | color(0, 1, 0)                   |
      | 3 | 1 | color(0, 0, 1)                   |
      | 0 | 2 | color(1, 1, 0)                   |
      | 1 | 2 | color(0, 1, 1)                   |
      | 2 | 2 | color(1, 0, 1)                   |
      | 3 | 2 | color(0.49804, 0.49804, 0.49804) |

  @chapter19
  Scenario: Comments in a PPM text are skipped wherever they are
    Given ppm ← a file containing:
      """
      P3 # plain PPM
      # the size, then the maximum value
      2 1
      255
      # the pixels
      255 255 255 # white
      # and purple
      255 0 255
      """
    When image ← canvas_from_ppm(ppm)
    Then pixel_at(image, 0, 0) = color(1, 1, 1)
      And pixel_at(image, 1, 0) = color(1, 0, 1)

  @chapter19
  Scenario: One pixel's values may be spread over several lines
    Given ppm ← a file containing:
      """
      P3
      1 1
      255
      51
      153

      204
      """
    When image ← canvas_from_ppm(ppm)
    Then pixel_at(image, 0, 0) = color(0.2, 0.6, 0.8)

  @chapter19
  Scenario: A PPM text's values are scaled by its maximum value
    Given ppm ← a file containing:
      """
      P3
      2 2
      100
      100 100 100  50 50 50
      75 50 25  0 0 0
      """
    When image ← canvas_from_ppm(ppm)
    Then pixel_at(image, 0, 1) = color(0.75, 0.5, 0.25)
      And pixel_at(image, 1, 0) = color(0.5, 0.5, 0.5)

  @chapter19
  Scenario: A PPM text with a value above its maximum is refused
    Given ppm ← a file containing:
      """
      P3
      1 1
      100
      0 101 0
      """
    Then canvas_from_ppm(ppm) should fail

  @chapter19
  Scenario: A PPM text with fewer values than its size says is refused
    Given ppm ← a file containing:
      """
      P3
      2 1
      255
      0 0 0  255 255
      """
    Then canvas_from_ppm(ppm) should fail

  @chapter19
  Scenario: A canvas written as PPM text reads back the same
    Given c ← canvas(3, 2)
      And write_pixel(c, 0, 0, color(1, 0, 0))
      And write_pixel(c, 2, 1, color(0, 0.2, 1))
    When image ← canvas_from_ppm(canvas_to_ppm(c))
    Then image.width = 3
      And image.height = 2
      And pixel_at(image, 0, 0) = color(1, 0, 0)
      And pixel_at(image, 2, 1) = color(0, 0.2, 1)
      And pixel_at(image, 1, 1) = color(0, 0, 0)

  # ---------------------------------------------------------------- image textures

  # A diagonal ramp of grays: pixel (x, y) is ((x + y) % 10) / 10. (u, v) = (0, 0) is the
  # image's bottom left pixel, (0, 9).
  @chapter19
  Scenario Outline: An image as a UV pattern
    Given ppm ← a file containing:
      """
      P3
      10 10
      10
      0 0 0  1 1 1  2 2 2  3 3 3  4 4 4  5 5 5  6 6 6  7 7 7  8 8 8  9 9 9
      1 1 1  2 2 2  3 3 3  4 4 4  5 5 5  6 6 6  7 7 7  8 8 8  9 9 9  0 0 0
      2 2 2  3 3 3  4 4 4  5 5 5  6 6 6  7 7 7  8 8 8  9 9 9  0 0 0  1 1 1
      3 3 3  4 4 4  5 5 5  6 6 6  7 7 7  8 8 8  9 9 9  0 0 0  1 1 1  2 2 2
      4 4 4  5 5 5  6 6 6  7 7 7  8 8 8  9 9 9  0 0 0  1 1 1  2 2 2  3 3 3
      5 5 5  6 6 6  7 7 7  8 8 8  9 9 9  0 0 0  1 1 1  2 2 2  3 3 3  4 4 4
      6 6 6  7 7 7  8 8 8  9 9 9  0 0 0  1 1 1  2 2 2  3 3 3  4 4 4  5 5 5
      7 7 7  8 8 8  9 9 9  0 0 0  1 1 1  2 2 2  3 3 3  4 4 4  5 5 5  6 6 6
      8 8 8  9 9 9  0 0 0  1 1 1  2 2 2  3 3 3  4 4 4  5 5 5  6 6 6  7 7 7
      9 9 9  0 0 0  1 1 1  2 2 2  3 3 3  4 4 4  5 5 5  6 6 6  7 7 7  8 8 8
      """
      And image ← canvas_from_ppm(ppm)
      And pattern ← uv_image(image)
    When c ← uv_pattern_at(pattern, <u>, <v>)
    Then c = <expected>

    Examples:
      | u   | v   | expected             |
      | 0   | 0   | color(0.9, 0.9, 0.9) |
      | 0.3 | 0   | color(0.2, 0.2, 0.2) |
      | 0.6 | 0.3 | color(0.1, 0.1, 0.1) |
      | 1   | 1   | color(0.9, 0.9, 0.9) |
      | 0   | 1   | color(0, 0, 0)       |

Feature: Canvas
  A rectangular grid of colours that can be written pixel by pixel and saved as a plain-text
  PPM image.

  @chapter02
  Scenario: A new canvas is black everywhere
    Given c ← canvas(10, 20)
    Then c.width = 10
      And c.height = 20
      And every pixel of c is color(0, 0, 0)

  @chapter02
  Scenario: A pixel written to the canvas can be read back
    Given c ← canvas(10, 20)
      And red ← color(1, 0, 0)
    When write_pixel(c, 2, 3, red)
    Then pixel_at(c, 2, 3) = red

  # The header: the magic number, the width and height, and the largest colour value.
  @chapter02
  Scenario: The PPM output starts with a three-line header
    Given c ← canvas(5, 3)
    When ppm ← canvas_to_ppm(c)
    Then lines 1-3 of ppm are
      """
      P3
      5 3
      255
      """

  # Channels are scaled to 0-255 and clamped: 1.5 becomes 255, -0.5 becomes 0, 0.5 rounds to 128.
  @chapter02
  Scenario: The PPM output lists the pixels row by row after the header
    Given c ← canvas(5, 3)
      And c1 ← color(1.5, 0, 0)
      And c2 ← color(0, 0.5, 0)
      And c3 ← color(-0.5, 0, 1)
    When write_pixel(c, 0, 0, c1)
      And write_pixel(c, 2, 1, c2)
      And write_pixel(c, 4, 2, c3)
      And ppm ← canvas_to_ppm(c)
    Then lines 4-6 of ppm are
      """
      255 0 0 0 0 0 0 0 0 0 0 0 0 0 0
      0 0 0 0 0 0 0 128 0 0 0 0 0 0 0
      0 0 0 0 0 0 0 0 0 0 0 0 0 0 255
      """

  # No line of a PPM file may be longer than 70 characters, so each 30-number row wraps
  # after 17 numbers; a line never ends with a space.
  @chapter02
  Scenario: Long rows of pixel data are wrapped to fit the line limit
    Given c ← canvas(10, 2)
    When every pixel of c is set to color(1, 0.8, 0.6)
      And ppm ← canvas_to_ppm(c)
    Then lines 4-7 of ppm are
      """
      255 204 153 255 204 153 255 204 153 255 204 153 255 204 153 255 204
      153 255 204 153 255 204 153 255 204 153 255 204 153
      255 204 153 255 204 153 255 204 153 255 204 153 255 204 153 255 204
      153 255 204 153 255 204 153 255 204 153 255 204 153
      """

  @chapter02
  Scenario: The PPM output ends with a newline
    Given c ← canvas(5, 3)
    When ppm ← canvas_to_ppm(c)
    Then ppm ends with a newline character

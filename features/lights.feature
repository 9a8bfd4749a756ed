Feature: Lights
  A point light: a position in space and the colour (intensity) of the light it gives off.

  # `position` is a variable here; it hides the function position(r, t) from chapter 5.
  @chapter06
  Scenario: A point light keeps its position and intensity
    Given intensity ← color(1, 1, 1)
      And position ← point(0, 0, 0)
    When light ← point_light(position, intensity)
    Then light.position = position
      And light.intensity = intensity
